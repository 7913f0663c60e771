"""report.json and the part file. Writing is all-or-nothing: files go to temporary names in the
output directory and are renamed into place only when every one was written."""
from __future__ import annotations

import json
import os

import numpy as np


def _round(v: float, nd: int = 6) -> float:
    r = round(float(v), nd)
    return 0.0 if r == 0 else r


def build_report(*, program: str, dialect: str, machine, blocks: int, moves: int, stock_volume: float,
                 part_volume: float, cycle_time: float, warnings: list, final_position, tolerance: float,
                 triangles: int, checks: list | None = None, last_cut_position=None) -> dict:
    """The report.json dict (fields documented in docs/setup.md, "report.json")."""
    return {
        "program": program,
        "dialect": dialect,
        "machine": {"kind": machine.kind, "diameter_programming": machine.diameter_programming, "m03": machine.m03},
        "tolerance": tolerance,
        "blocks": blocks,
        "moves": moves,
        "stock_volume": _round(stock_volume),
        "part_volume": _round(part_volume),
        "removed_volume": _round(stock_volume - part_volume),
        "cycle_time_s": _round(cycle_time, 3),
        "final_position": [_round(v) for v in final_position],
        "last_cut_position": None if last_cut_position is None else [_round(v) for v in last_cut_position],
        "triangles": triangles,
        "warnings": [_warning(src, msg) for src, msg in warnings],
        "checks": checks or [],
    }


def _warning(src, message: str) -> dict:
    """One warning record. For a line of a subprogram body ``called_from`` lists the call sites'
    lines, the direct caller first, and ``called_from_programs`` their files when one is not the
    warning's own file (a Sinumerik NAME.spf called from the main program)."""
    w = {"line": src.line, "column": src.col, "program": src.program, "message": message}
    if src.calls:
        sites = list(reversed(src.calls))
        w["called_from"] = [line for _program, line in sites]
        if any(program != src.program for program, _line in sites):
            w["called_from_programs"] = [program for program, _line in sites]
    return w


def called_from(w: dict) -> str:
    """' (called from P:40, from P:12)' for a warning record from a subprogram body, else ''."""
    lines = w.get("called_from") or []
    if not lines:
        return ""
    programs = w.get("called_from_programs") or [w["program"]] * len(lines)
    return " (called from " + ", from ".join(f"{p}:{line}" for p, line in zip(programs, lines)) + ")"


def warning_text(w: dict) -> str:
    """A warning record as the CLI prints it: ``PROGRAM:LINE:COL: warning: TEXT (called from ...)``."""
    return f"{w['program']}:{w['line']}:{w['column']}: warning: {w['message']}{called_from(w)}"


def mesh_arrays(part):
    """Vertices (float64) and faces of a manifold, in a deterministic order."""
    mesh = part.to_mesh()
    verts = np.asarray(mesh.vert_properties, dtype=np.float64)[:, :3]
    faces = np.asarray(mesh.tri_verts, dtype=np.int64)
    return verts, faces


def stl_bytes(verts: np.ndarray, faces: np.ndarray) -> bytes:
    """Binary STL with unit normals, little-endian, zero header: same mesh, same bytes."""
    tri = verts[faces].astype(np.float64)
    nrm = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    ln = np.linalg.norm(nrm, axis=1, keepdims=True)
    nrm = np.divide(nrm, ln, out=np.zeros_like(nrm), where=ln > 0)
    rec = np.zeros(len(faces), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["n"] = nrm
    rec["v"] = tri
    header = b"cutsim binary STL".ljust(80, b"\0")
    return header + np.uint32(len(faces)).astype("<u4").tobytes() + rec.tobytes()


def report_bytes(report: dict) -> bytes:
    return (json.dumps(report, indent=2, ensure_ascii=False, sort_keys=False) + "\n").encode("utf-8")


def part_bytes(verts: np.ndarray, faces: np.ndarray, fmt: str = "stl") -> bytes:
    """The part file in ``fmt``: "stl" (stl_bytes), "3mf" (threemf_bytes) or "glb" (trimesh's
    exporter). Same mesh, same bytes for all three: the 3MF zip has fixed entry dates and GLB
    carries no timestamps."""
    if fmt == "stl":
        return stl_bytes(verts, faces)
    if fmt == "3mf":
        return threemf_bytes(verts, faces)
    import trimesh

    mesh = trimesh.Trimesh(vertices=verts, faces=faces, process=False)
    if fmt == "glb":
        return trimesh.exchange.gltf.export_glb(trimesh.Scene(mesh))
    raise ValueError(f"unknown part format {fmt!r}")


def threemf_bytes(verts: np.ndarray, faces: np.ndarray) -> bytes:
    """A minimal 3MF package (core spec: one mesh object, unit millimetre), written without lxml;
    zip entries carry a fixed date so the bytes depend only on the mesh."""
    import io
    import zipfile

    v = "".join(f'<vertex x="{x:.9g}" y="{y:.9g}" z="{z:.9g}"/>' for x, y, z in np.asarray(verts, dtype=np.float64))
    t = "".join(f'<triangle v1="{a}" v2="{b}" v3="{c}"/>' for a, b, c in np.asarray(faces, dtype=np.int64))
    model = ('<?xml version="1.0" encoding="UTF-8"?>\n'
             '<model unit="millimeter" xml:lang="en-US" '
             'xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02">'
             '<resources><object id="1" type="model" name="part"><mesh>'
             f"<vertices>{v}</vertices><triangles>{t}</triangles></mesh></object></resources>"
             '<build><item objectid="1"/></build></model>\n')
    types = ('<?xml version="1.0" encoding="UTF-8"?>\n'
             '<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">'
             '<Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/>'
             '<Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/>'
             "</Types>\n")
    rels = ('<?xml version="1.0" encoding="UTF-8"?>\n'
            '<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">'
            '<Relationship Target="/3D/3dmodel.model" Id="rel0" '
            'Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>\n')
    buf = io.BytesIO()
    with zipfile.ZipFile(buf, "w", compression=zipfile.ZIP_DEFLATED) as z:
        for name, text in (("[Content_Types].xml", types), ("_rels/.rels", rels), ("3D/3dmodel.model", model)):
            info = zipfile.ZipInfo(name, date_time=(1980, 1, 1, 0, 0, 0))
            info.compress_type = zipfile.ZIP_DEFLATED
            info.external_attr = 0o644 << 16
            z.writestr(info, text.encode("utf-8"))
    return buf.getvalue()
