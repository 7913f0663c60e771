"""report.html: one self-contained page (no scripts, no network: the images are inlined as base64
data URIs, so the file opens from the output folder or anywhere else it is copied to).

Rendered with jinja2 from ``templates/report.html.j2`` (package data): the verdict, a summary
table with units, the setup (stock, tools, tolerance), the checks (each linked to its
``[[check]]`` line in a numbered copy of the setup file at the end of the page), the warnings
(programs named relative to the directory cutsim was run from), the images with captions and the
versions of cutsim, manifold3d and VTK.
"""
from __future__ import annotations

import base64
import io
import os

from .report import called_from


def _fmt(v, nd: int = 6) -> str:
    if v is None:
        return "\u2014"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, (int, float)):
        s = f"{v:.{nd}g}" if isinstance(v, float) else str(v)
        return s.replace("-", "\u2212")  # a true minus sign, as in the images
    return str(v)


def _num(v, nd: int = 3) -> str:
    """A fixed-point number with thousands separators and a true minus sign."""
    if v is None:
        return "\u2014"
    s = f"{float(v):,.{nd}f}"
    return s.replace("-", "\u2212")


def rel_path(path: str, start: str | None = None) -> str:
    """``path`` relative to ``start`` (the current directory): no absolute machine paths in the report."""
    if not path or not os.path.isabs(path):
        return path
    try:
        return os.path.relpath(path, start or os.getcwd())
    except ValueError:  # another drive (Windows)
        return os.path.basename(path)


def _clock(seconds: float) -> str:
    m, s = divmod(float(seconds), 60.0)
    h, m = divmod(int(m), 60)
    return f"{h}:{m:02d}:{s:04.1f}" if h else f"{m}:{s:04.1f}"


def _summary(report: dict) -> list[tuple[str, str, str]]:
    m = report.get("machine") or {}
    rows = [("program", report.get("program", ""), ""), ("dialect", report.get("dialect", ""), "")]
    if m:
        kind = m.get("kind", "")
        if kind == "lathe":
            kind += ", X in diameters" if m.get("diameter_programming") else ", X in radii"
        rows.append(("machine", kind, ""))
    rows += [("blocks", _fmt(report.get("blocks")), ""), ("moves", _fmt(report.get("moves")), ""),
             ("stock volume", _num(report.get("stock_volume")), "mm\u00b3"),
             ("part volume", _num(report.get("part_volume")), "mm\u00b3"),
             ("removed volume", _num(report.get("removed_volume")), "mm\u00b3")]
    ct = report.get("cycle_time_s")
    if ct is not None:
        rows.append(("cycle time", f"{_num(ct)} ({_clock(ct)} min:s)", "s"))
    if report.get("tolerance") is not None:
        rows.append(("chordal tolerance", _fmt(report["tolerance"]), "mm"))
    if report.get("triangles") is not None:
        rows.append(("part triangles", f"{report['triangles']:,}", ""))
    for key, label in (("final_position", "final position X Y Z"), ("last_cut_position", "last cut position X Y Z")):
        p = report.get(key)
        if p:
            rows.append((label, "  ".join(_num(v) for v in p), "mm"))
    return rows


def _stock_text(stock, setup_dir: str) -> str:
    return _stock_words(stock, setup_dir).replace("-", "\u2212") if stock.shape != "mesh" else \
        _stock_words(stock, setup_dir)


def _stock_words(stock, setup_dir: str) -> str:
    s = stock.shape
    if s == "cylinder":
        return f"cylinder \u00d8{stock.diameter:g} mm, Z {stock.z[0]:g} \u2026 {stock.z[1]:g} mm"
    if s == "revolve":
        pts = ", ".join(f"({r:g}, {z:g})" for r, z in stock.profile)
        return f"revolved profile (r, z) mm: {pts}"
    if s == "box":
        return (f"box X {stock.x[0]:g} \u2026 {stock.x[1]:g}, Y {stock.y[0]:g} \u2026 {stock.y[1]:g}, "
                f"Z {stock.z[0]:g} \u2026 {stock.z[1]:g} mm")
    return f"{s} {rel_path(stock.path, setup_dir) if stock.path else ''}".strip()


def _tool_geometry(t) -> str:
    if t.kind in ("thread", "turning"):
        return f"included angle {t.angle:g}\u00b0, nose radius {t.tip_radius:g} mm"
    if t.kind == "profile":
        return f"profile of {len(t.points)} points"
    out = f"\u00d8{t.diameter:g} mm"
    if t.length:
        out += f", flute length {t.length:g} mm"
    if t.corner_radius and t.kind != "ballmill":
        out += f", corner radius {t.corner_radius:g} mm"
    if t.kind == "drill":
        out += f", point angle {t.point_angle:g}\u00b0"
    if t.name:
        out += f", name \u201c{t.name}\u201d"
    return out


def _versions() -> list[tuple[str, str]]:
    from importlib import metadata

    out = []
    for dist in ("cutsim", "manifold3d"):
        try:
            out.append((dist, metadata.version(dist)))
        except metadata.PackageNotFoundError:  # pragma: no cover
            out.append((dist, "?"))
    try:
        from vtkmodules.vtkCommonCore import vtkVersion

        out.append(("VTK", vtkVersion.GetVTKVersion()))
    except ImportError:  # pragma: no cover - images need VTK; a report without images may not have it
        pass
    return out


def _png_size(data: bytes) -> tuple[int, int]:
    from PIL import Image

    with Image.open(io.BytesIO(data)) as im:
        return im.size


def _environment():
    import jinja2

    return jinja2.Environment(loader=jinja2.PackageLoader("cutsim.reports", "templates"),
                              autoescape=jinja2.select_autoescape(["html", "j2"]), keep_trailing_newline=True)


def report_html(report: dict, images: dict[str, bytes] | None = None, *, captions: dict | None = None,
                setup=None, order: list[str] | None = None) -> bytes:
    """The HTML report for ``report`` (the report.json dict) with ``images`` ({name: PNG bytes},
    shown in ``order`` or sorted, each with ``captions[name]``) and ``setup`` (a cutsim Setup: stock,
    tools, the setup file's text for the links from the checks)."""
    checks = report.get("checks", [])
    failed = [c for c in checks if not c["passed"]]
    if not checks:
        verdict = {"cls": "none", "word": "", "text": "no checks in the setup"}
    elif failed:
        verdict = {"cls": "fail", "word": "FAILED",
                   "text": f"FAIL: {len(failed)} of {len(checks)} check(s) failed ("
                           + ", ".join(c["name"] for c in failed) + ")"}
    else:
        verdict = {"cls": "pass", "word": "passed", "text": f"PASS: all {len(checks)} check(s) passed"}
    rows = []
    for c in checks:
        items = []
        for it in c["items"] or [{"quantity": "", "expected": None, "measured": None, "tolerance": None,
                                  "unit": "", "passed": False}]:
            e, m = it["expected"], it["measured"]
            diff = None
            if isinstance(e, (int, float)) and isinstance(m, (int, float)) and not isinstance(e, bool) \
                    and it.get("tolerance") is not None:
                diff = float(m) - float(e)
            items.append({"quantity": it["quantity"], "expected": _fmt(e), "measured": _fmt(m),
                          "diff": "" if diff is None else _fmt(round(diff, 6)),
                          "tolerance": "" if it["tolerance"] is None else f"\u00b1{_fmt(it['tolerance'])}",
                          "unit": it["unit"].replace("mm^3", "mm\u00b3"), "passed": it["passed"]})
        rows.append({"name": c["name"], "kind": c["kind"], "line": c.get("line", 0), "rows": items})
    warnings = [f"{rel_path(w['program'])}:{w['line']}:{w['column']}: warning: {w['message']}"
                + called_from(w).replace(w["program"], rel_path(w["program"])) for w in report.get("warnings", [])]
    setup_rows, tools, setup_lines, setup_name = [], [], [], "setup"
    if setup is not None:
        setup_name = os.path.basename(setup.path) or "setup"
        sdir = os.path.dirname(os.path.abspath(setup.path)) if setup.path else None
        setup_rows = [("setup file", rel_path(os.path.abspath(setup.path)) if setup.path else ""),
                      ("stock", _stock_text(setup.stock, sdir)),
                      ("chordal tolerance", f"{report.get('tolerance', setup.tolerance):g} mm")]
        tools = [{"number": t.number, "kind": t.kind, "geometry": _tool_geometry(t)} for t in setup.tools]
        try:
            with open(setup.path, encoding="utf-8", errors="replace") as f:
                setup_lines = f.read().splitlines()
        except (OSError, TypeError, ValueError):
            setup_lines = []
    names = list(order) if order else sorted(images or {})
    imgs = []
    for name in names:
        data = (images or {})[name]
        w, h = _png_size(data)
        imgs.append({"name": name, "caption": (captions or {}).get(name, ""), "width": w, "height": h,
                     "data": base64.b64encode(data).decode("ascii")})
    text = _environment().get_template("report.html.j2").render(
        program=report.get("program", ""), verdict=verdict, summary=_summary(report), setup_rows=setup_rows,
        tools=tools, checks=rows, warnings=warnings, images=imgs, setup_lines=setup_lines, setup_name=setup_name,
        versions=_versions())
    return text.encode("utf-8")
