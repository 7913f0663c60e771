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
import math
import os
from decimal import Decimal

from .report import called_from


def decimals(tol) -> int:
    """The decimals a number (a tolerance) is written with: 0.02 -> 2, 0.005 -> 3, 2 -> 0,
    1e-05 -> 5; 3 for no number."""
    if tol is None or not math.isfinite(float(tol)):
        return 3
    if float(tol) == 0:
        return 0
    return max(0, -Decimal(repr(abs(float(tol)))).normalize().as_tuple().exponent)


def _fixed(v: float, nd: int, sep: bool = False) -> str:
    """``v`` to ``nd`` decimals with a true minus sign; a value that rounds to zero has no sign."""
    r = round(float(v), nd)
    s = f"{0.0 if r == 0 else r:{',' if sep else ''}.{nd}f}"
    return s.replace("-", "\u2212")


def _fmt(v, nd: int = 3) -> str:
    """A value of the report: None as a dash, booleans as yes/no, integers as they are (thousands
    separated), floats to ``nd`` decimals; anything else as text."""
    if v is None:
        return "\u2014"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, int):
        return f"{v:,}".replace("-", "\u2212")
    if isinstance(v, float):
        return _fixed(v, nd)
    return str(v)


def _num(v, nd: int = 3) -> str:
    """A fixed-point number with thousands separators and a true minus sign."""
    if v is None:
        return "\u2014"
    return _fixed(v, nd, sep=True)


def _item_row(it: dict, default_nd: int) -> dict:
    """One check item as table cells. Expected, measured and their difference share one format:
    one decimal more than the tolerance is written with (the measuring resolution a tenth of the
    band: +-0.02 -> 3 decimals, +-0.005 -> 4, +-2 deg -> 1), more when the expected value is written
    with more (up to 6), and more again (up to 6) while the rounded difference would read against
    the item's verdict (a failed item never shows a difference inside its tolerance)."""
    e, m, tol = it["expected"], it["measured"], it.get("tolerance")
    numeric = all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in (e, m))
    nd = default_nd if tol is None else decimals(tol) + 1
    if isinstance(e, float):
        nd = max(nd, min(6, decimals(e)))
    diff = None
    if numeric and tol is not None:
        diff = float(m) - float(e)
        while nd < 6 and (abs(round(diff, nd)) > float(tol)) == bool(it["passed"]):
            nd += 1
    return {"quantity": it["quantity"], "expected": _fmt(e, nd), "measured": _fmt(m, nd),
            "diff": "" if diff is None else _fixed(diff, nd),
            "tolerance": "" if tol is None else f"\u00b1{float(tol):g}".replace("-", "\u2212"),
            "unit": it["unit"].replace("mm^3", "mm\u00b3"), "passed": it["passed"]}


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
    """The summary rows (quantity, value, unit). Volumes and positions are written to the chordal
    tolerance's decimals (0.005 -> 3): the part is not made finer than that. A lathe's positions
    say whether X is a diameter or a radius (program values, as the controller shows them)."""
    m = report.get("machine") or {}
    nd = decimals(report.get("tolerance"))
    rows = [("program", report.get("program", ""), ""), ("dialect", report.get("dialect", ""), "")]
    x_word = "X"
    if m:
        kind = m.get("kind", "")
        if kind == "lathe":
            kind += ", X in diameters" if m.get("diameter_programming") else ", X in radii"
            x_word = "X (diameter)" if m.get("diameter_programming") else "X (radius)"
        rows.append(("machine", kind, ""))
    rows += [("blocks", _fmt(report.get("blocks")), ""), ("moves", _fmt(report.get("moves")), ""),
             ("stock volume", _num(report.get("stock_volume"), nd), "mm\u00b3"),
             ("part volume", _num(report.get("part_volume"), nd), "mm\u00b3"),
             ("removed volume", _num(report.get("removed_volume"), nd), "mm\u00b3")]
    ct = report.get("cycle_time_s")
    if ct is not None:
        rows.append(("cycle time", f"{_num(ct)} ({_clock(ct)} min:s)", "s"))
    if report.get("tolerance") is not None:
        rows.append(("chordal tolerance", f"{float(report['tolerance']):g}", "mm"))
    if report.get("triangles") is not None:
        rows.append(("part triangles", _fmt(report["triangles"]), ""))
    for key, label in (("final_position", "final position"), ("last_cut_position", "last cut position")):
        p = report.get(key)
        if p:
            rows.append((f"{label} {x_word} Y Z", "\u2003".join(_num(v, nd) for v in p), "mm"))
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
    """The tools table's description of a tool: a lathe tool's insert (and its holder or boring
    bar), an axial tool's kind and sizes (``_axial_geometry``), a mill's diameter and flutes."""
    if t.kind in ("drill", "centredrill", "tap"):
        out = _axial_geometry(t)
    elif t.kind in ("thread", "turning", "grooving", "profile"):
        out = _lathe_geometry(t)
    else:
        out = f"\u00d8{t.diameter:g} mm"
        if t.length:
            out += f", flute length {t.length:g} mm"
        if t.corner_radius and t.kind != "ballmill":
            out += f", corner radius {t.corner_radius:g} mm"
    if t.name:
        out += f", name \u201c{t.name}\u201d"
    return out


def _lathe_geometry(t) -> str:
    where = "" if t.side == "outside" else f", {t.side}"
    if t.kind == "profile":
        return f"profile of {len(t.points)} points"
    if t.kind == "turning" and t.insert:
        from cutsim.stock.inserts import approach_of

        out = (f"ISO insert {t.insert} {t.size:g} mm, nose radius {t.tip_radius:g} mm, approach "
               f"{approach_of(t):g}\u00b0, hand {t.hand}{where}")
    elif t.kind == "thread" and t.form == "full":
        crest = f", crest radius {t.crest_radius:g} mm" if t.crest_radius else ""
        out = f"full-profile ISO metric insert P {t.pitch:g} mm, root radius {t.tip_radius:g} mm{crest}{where}"
    elif t.kind == "grooving":
        out = f"grooving insert {t.width:g} mm wide, corner radius {t.corner_radius:g} mm, hand {t.hand}{where}"
    else:
        out = f"included angle {t.angle:g}\u00b0, nose radius {t.tip_radius:g} mm{where}"
    if t.shank:
        out += f"; holder shank {t.shank:g} \u00d7 {t.shank:g} mm"
        if t.kind == "thread" and t.hand != "R":  # the insert is neutral: its hand is the holder's
            out += f", hand {t.hand}"
    if t.bar_diameter:
        from cutsim.stock.inserts import bar_reach

        out += f"; boring bar \u00d8{t.bar_diameter:g} mm, its axis {bar_reach(t):g} mm from the tool point"
    return out


def _axial_geometry(t) -> str:
    """A twist drill (diameter, point angle, flute length), a centre drill (pilot, its point and
    length, countersink angle up to the body's diameter) or a tap (its ISO designation M d x P, the
    thread length and the chamfered lead)."""
    point = "flat end" if t.point_angle >= 180.0 else f"point angle {t.point_angle:g}\u00b0"
    if t.kind == "drill":
        return f"twist drill \u00d8{t.diameter:g} mm, {point}, flute length {t.length:g} mm"
    if t.kind == "centredrill":
        return (f"centre drill, pilot \u00d8{t.diameter:g} mm ({point}, {t.pilot_length:g} mm to the countersink), "
                f"countersink {t.countersink:g}\u00b0 to \u00d8{t.body_diameter:g} mm, length {t.length:g} mm")
    return (f"tap M{t.diameter:g}\u00d7{t.pitch:g} (\u00d8{t.diameter:g} mm, pitch {t.pitch:g} mm), thread length "
            f"{t.length:g} mm, chamfered lead {t.chamfer:g} mm")


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
    nd = decimals(report.get("tolerance")) + 1
    rows = []
    for c in checks:
        items = [_item_row(it, nd) for it in c["items"] or [{"quantity": "", "expected": None, "measured": None,
                                                              "tolerance": None, "unit": "", "passed": False}]]
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
