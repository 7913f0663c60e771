"""Off-screen PNG views of a result (``cutsim simulate ... --images``). pyvista is imported inside
the functions only, so the rest of cutsim works without it.

Every view is WIDTH pixels wide on white, HEIGHT high except ``section.png``, whose height follows
the part's proportions (a slender shaft is not drawn into a mostly empty page). The 2D views
(sections, the top view) are drawn in parallel projection at one scale in both directions (mm
are mm), framed by rulers whose ticks are round numbers in true workpiece coordinates (a part at
Z-30..0 reads -30..0, a thread at radius 10.5..13.5 reads 10.5..13.5); their labels are text
actors of the plotter (:class:`View`). All views follow one camera convention (see
:mod:`cutsim.reports.views3d`): on a mill X to the right and Y away from the viewer, on a lathe Z
to the right and X up.

Lathe:
- ``iso.png``: the part as it sits in the lathe, the stock's outline and axes with round ticks;
- ``section.png``: the full-length half-section near C0 (the half-plane through +X, moved under 1
  degree clear of construction seams, ``section_angle``): part in grey,
  the material removed from the stock in orange, the stock outline in red; Z along the bottom,
  the radius on the left and the diameter on the right;
- ``thread-N.png`` for the N-th ``thread`` check: two and a half pitches around the middle of its
  range at that angle with the measured root and crest diameters, the pitch and both flank angles;
- ``ramp-N.png`` for the N-th ``ramp`` check (lead-in, runout): the section at that angle over the
  ramp with the root radius measured over all angles and the ramp the check expects.

Mill:
- ``top.png``: the part from above coloured over the cut depth range (stock top to deepest floor),
  one colour per distinct floor (a legend lists their Z), continuous with contour lines when the
  part has more than MAX_FLOORS flat levels; the rulers' ticks span the stock;
- ``iso.png``: from the front left above, floors in the same colours as the top view, walls grey,
  the part's edges dark;
- with a design check, ``deviation.png``: each face of the part coloured by its signed distance
  to the design (cell data; blue = gouge, red = excess) on a diverging scale symmetric about 0,
  clipped to +-DEV_K x tolerance, the tolerance band neutral, lit and edged as iso.png; the worst
  gouge and excess labelled.
"""
from __future__ import annotations

import math

import numpy as np

from cutsim.stock.arrays import solid_arrays

from .plot import (HEIGHT, MAX_FLOORS, PART_COLOR, REMOVED_COLOR, STOCK_COLOR, WALL_COLOR, WIDTH, View,
                   _Chart, _face_floor_index, _floor_colors, _mesh, _num, _polydata, _plotter, _pv, _rgb,
                   _stock_outline, floor_levels)
from .plot import DEV_K, nice_step, nice_ticks, text_actors  # noqa: F401 - re-exported: the images' API
from .views3d import deviation_view, face_deviation, iso_view  # noqa: F401 - re-exported: the images' API

SECTION_MIN_HEIGHT = 360  # px: section.png is at least this high, at most HEIGHT


def _swap(polys):
    """(r, z) polygons as (z, r), orientation kept (reversed order: the swap mirrors them)."""
    return [np.ascontiguousarray(np.asarray(q)[::-1, ::-1]) for q in polys]


def _cs(polys):
    from manifold3d import CrossSection

    return CrossSection([np.asarray(q, dtype=float) for q in polys if len(q) >= 3])


def _rect(u0, u1, v0, v1):
    from manifold3d import CrossSection

    return CrossSection.square((u1 - u0, v1 - v0)).translate((u0, v0))


def _polys(cs):
    return [np.asarray(q, dtype=float) for q in cs.to_polygons() if len(q) >= 3]


# ------------------------------------------------------------------------------------------------
# lathe
# ------------------------------------------------------------------------------------------------
def section_angle(result) -> float:
    """The angle of the lathe images' half-sections: C0 moved (by under 1 degree) to the plane
    clearest of the part's and the stock's construction seams, as the thread check's sections are
    (measure.seam_free_angles): the plane at exactly C0 holds the seams of revolved solids and of
    threads cut from the zero pulse, where a section can come out wrong."""
    from cutsim.reports import measure as M

    return float(M.seam_free_angles([result.part, result.stock], [0.0])[0][0])


def _lathe_sections(result, window=None, phi: float | None = None):
    """(part, stock, removed) half-sections at ``phi`` (default ``section_angle``) as (z, r)
    polygon lists, clipped to ``window``."""
    from cutsim.reports import measure as M

    phi = section_angle(result) if phi is None else phi
    part = _cs(_swap(M.half_plane_section(result.part, phi)))
    stock = _cs(_swap(M.half_plane_section(result.stock, phi)))
    removed = stock - part
    if window is not None:
        w = _rect(*window)
        part, stock, removed = part ^ w, stock ^ w, removed ^ w
    return _polys(part), _polys(stock), _polys(removed)


def section_view(result) -> View:
    """Lathe: the full-length half-section near C0 (``section_angle``) in true coordinates (Z
    across, radius up)."""
    sb = result.stock.bounding_box()
    pb = result.part.bounding_box()
    z0, z1 = min(sb[2], pb[2]), max(sb[5], pb[5])
    rmax = max(abs(v) for v in (sb[0], sb[1], sb[3], sb[4], pb[0], pb[1], pb[3], pb[4]))
    mz = 0.06 * (z1 - z0) + 0.5
    margins = (80, 80, 70, 85)
    s_est = (WIDTH - margins[0] - margins[1]) / (z1 - z0 + 2 * mz)  # px per mm when the length fills the width
    mr = 0.12 * rmax + 0.5 + 64.0 / s_est  # room above the part for the checks' brackets
    # the image as high as the part drawn across the width needs, within [SECTION_MIN_HEIGHT, HEIGHT]
    need = (rmax + mr) * s_est + margins[2] + margins[3]
    p = _plotter(size=(WIDTH, 2 * int(math.ceil(min(HEIGHT, max(SECTION_MIN_HEIGHT, need)) / 2))))
    ch = _Chart(p, (z0 - mz, z1 + mz, 0.0, rmax + mr), margins=margins, anchor_v0=True, widen_v=False)
    phi = section_angle(result)
    part, stock, removed = _lathe_sections(result, phi=phi)
    ch.fill(part, PART_COLOR)
    ch.fill(removed, REMOVED_COLOR, dz=0.1)
    ch.lines(part, color="#333333", width=1.0, dz=0.5)
    ch.lines([np.vstack([q, q[:1]]) for q in stock], color=STOCK_COLOR, width=2.0, dz=0.8)
    u0, u1 = ch.box[:2]
    ch.lines([((u0, 0.0), (u1, 0.0))], color="#555555", width=1.0, dashed=True, dz=0.9)
    ch.axes("Z mm", "radius mm", v2=lambda r: 2 * r, v2title="\u00d8 mm")
    _mark_checks(ch, result)
    ch.title(f"{result.report.get('program', '')}: half-section at C{_num(phi, 2)}\u00b0 (+X), "
             f"Z {_num(z0, 2)} \u2026 {_num(z1, 2)}")
    ch.legend([("part", PART_COLOR), ("removed", REMOVED_COLOR), ("stock outline", STOCK_COLOR)])
    return View("section.png", f"Half-section at C{_num(phi, 2)}\u00b0 (the half-plane through +X, moved off C0 "
                "clear of construction seams) in workpiece coordinates: part grey, removed material orange, "
                "stock outline red; radius left, diameter right.",
                p, ch.ticks, pixel=ch.pixel)


def _mark_checks(ch, result):
    """The z ranges of the thread and ramp checks as labelled brackets above the part."""
    _u0, _u1, _v0, v1 = ch.box
    k = 0
    for spec in result.setup.checks:
        if spec["kind"] not in ("thread", "ramp", "diameter"):
            continue
        if spec["kind"] == "diameter":
            za = zb = spec["z"]
        else:
            za, zb = spec["z"]
        v = v1 - ch.px(14 + 18 * (k % 3))
        k += 1
        if za == zb:
            ch.lines([((za, v), (za, v - ch.px(10)))], color="#1f5fa8", width=2.0, dz=1.2)
        else:
            ch.lines([((za, v - ch.px(5)), (za, v), (zb, v), (zb, v - ch.px(5)))], color="#1f5fa8", width=2.0,
                     dz=1.2)
        ch.text(max(za, zb) + ch.px(4), v, spec["name"], size=11, color="#1f5fa8", halign="left")


def _fit_flank(z, r, lo, hi):
    """Angle (degrees) between the radial direction and the line fitted to the profile points with
    radius in [lo, hi], and the fit (z = a r + b)."""
    sel = (r >= lo) & (r <= hi)
    if np.count_nonzero(sel) < 2 or np.ptp(r[sel]) <= 0:
        return None, None
    a, b = np.polyfit(r[sel], z[sel], 1)
    return math.degrees(math.atan(abs(a))), (float(a), float(b))


def thread_view(result, spec, index: int) -> View:
    """Lathe: 2.5 pitches of the ``thread`` check ``spec`` around the middle of its range at the
    section angle (C0 moved clear of seams), with measured root and crest diameters, pitch and
    flank angles. An inside thread (``side``) is read on the bore's wall: its grooves run outwards,
    so the measuring works on u = -r (the groove's depth coordinate) and draws at r = s u."""
    from cutsim.reports import measure as M

    zlo, zhi = spec["z"]
    inside = spec.get("side") == "inside"
    s = -1.0 if inside else 1.0
    m = M.measure_thread(result.part, zlo, zhi, spec.get("angles", 36), inside=inside)
    pitch = m["pitch"] or spec["lead"] / max(1, spec["starts"])
    zc = 0.5 * (zlo + zhi)
    za, zb = zc - 1.25 * pitch, zc + 1.25 * pitch
    phi = section_angle(result)
    z, r = M.outer_profile(result.part, phi, za - pitch, zb + pitch, step=pitch / 400.0, inside=inside)
    ok = np.isfinite(r)
    z, r = z[ok], s * r[ok]  # r is the depth coordinate u from here; drawn at s u
    inwin = (z >= za) & (z <= zb)
    r_crest = float(r[inwin].max()) if np.any(inwin) else float(np.nanmax(r))
    roots = M.groove_roots(z, r)
    r_root_sec = float(roots[:, 1].min()) if len(roots) else float(r.min())
    h = max(r_crest - r_root_sec, 0.1 * pitch)
    v0, v1 = sorted((s * (r_root_sec - 0.55 * h), s * (r_crest + 0.45 * h)))
    p = _plotter()
    ch = _Chart(p, (za, zb, v0, v1), margins=(90, 90, 70, 85))
    win = ch.box
    part, stock, removed = _lathe_sections(result, win, phi)
    ch.fill(part, PART_COLOR)
    ch.fill(removed, REMOVED_COLOR, dz=0.1)
    ch.lines([np.vstack([q, q[:1]]) for q in part], color="#333333", width=1.2, dz=0.5)
    ch.axes("Z mm", "radius mm", v2=lambda x: 2 * x, v2title="\u00d8 mm", grid=True)
    u0, u1 = win[0], win[1]
    notes = []
    # root and crest levels
    d_root = m["root_diameter"]
    rr = s * d_root / 2 if d_root else r_root_sec
    ch.lines([((u0, s * rr), (u1, s * rr))], color="#1f5fa8", width=1.5, dashed=True, dz=1.0)
    ch.lines([((u0, s * r_crest), (u1, s * r_crest))], color="#2a8a3a", width=1.5, dashed=True, dz=1.0)
    root_txt = f"root \u00d8 {_num(d_root)}" if d_root else "root: not measured"
    if d_root and m["root_diameter_min"] is not None:
        root_txt += f"  ({_num(m['root_diameter_min'])} \u2026 {_num(m['root_diameter_max'])} over all angles)"
    if spec.get("root_diameter") is not None:
        root_txt += f"  check {_num(spec['root_diameter'])} \u00b1{spec['tolerance']:g}"
    crest_txt = f"crest \u00d8 {_num(2 * abs(r_crest))}"
    ch.text(u0 + ch.px(8), s * (rr - ch.px(6)), root_txt, size=13, color="#1f5fa8", halign="left",
            valign="bottom" if inside else "top", bold=True)
    ch.text(u0 + ch.px(8), s * (r_crest + ch.px(6)), crest_txt, size=13, color="#2a8a3a", halign="left",
            valign="top" if inside else "bottom", bold=True)
    notes += [root_txt, crest_txt]
    # roots in the window, pitch between the two nearest the middle
    rts = roots[(roots[:, 0] >= u0) & (roots[:, 0] <= u1)] if len(roots) else roots
    for zr, rv in rts:
        ch.marker(zr, s * rv, color="#1f5fa8")
    if len(rts) >= 2:
        k = int(np.argmin(np.abs(rts[:, 0] - zc)))
        k2 = k + 1 if k + 1 < len(rts) else k - 1
        a_, b_ = sorted((float(rts[k, 0]), float(rts[k2, 0])))
        vy = r_root_sec - 0.3 * h
        t = ch.px(6)
        ch.lines([((a_, s * vy), (b_, s * vy)), ((a_, s * (vy - t)), (a_, s * (vy + t))),
                  ((b_, s * (vy - t)), (b_, s * (vy + t))), ((a_, s * (vy + t)), (a_, s * rts[k, 1])),
                  ((b_, s * (vy + t)), (b_, s * rts[k2, 1]))], color="black", width=1.3, dz=1.2)
        ptxt = f"P {_num(b_ - a_)} here, {_num(pitch)} median  (lead {_num(m['lead']) if m['lead'] else '?'})"
        ch.text((a_ + b_) / 2, s * (vy - ch.px(8)), ptxt, size=13, valign="bottom" if inside else "top", bold=True)
        notes.append(ptxt)
    ftxt = _draw_flanks(ch, z, r, rts, zc, r_crest, h, s)  # flank angles of the groove nearest the middle
    if ftxt:
        notes.append(ftxt)
    name = spec["name"]
    ch.title(f"{name}: tooth detail at C{_num(phi, 2)}\u00b0 (+X); checked Z {_num(zlo, 2)} \u2026 {_num(zhi, 2)}, "
             f"{m['starts'] or '?'} start(s), {m['hand'] or '?'} hand")
    ch.legend([("part", PART_COLOR), ("removed", REMOVED_COLOR)])
    return View(f"thread-{index}.png", f"Thread check \u201c{name}\u201d: two and a half pitches at C{_num(phi, 2)}\u00b0 around "
                f"Z {_num(zc, 2)} with the measured root and crest diameters, pitch and flank angles.",
                p, ch.ticks, notes, pixel=ch.pixel)


def _draw_flanks(ch, z: np.ndarray, r: np.ndarray, rts: np.ndarray, zc: float, r_crest: float,
                 h: float, s: float = 1.0) -> str | None:
    """The flank angles of the groove nearest ``zc`` drawn on the tooth detail (``s`` -1 draws an
    inside thread's section below the axis); their note, or None when a flank was not measured."""
    if not len(rts):
        return None
    k = int(np.argmin(np.abs(rts[:, 0] - zc)))
    zr, rv = float(rts[k, 0]), float(rts[k, 1])
    depth = r_crest - rv
    lo, hi = rv + 0.2 * depth, rv + 0.8 * depth
    angs = []
    i0 = int(np.argmin(np.abs(z - zr)))
    for side in (-1, 1):
        j = i0  # walk up this flank from the root to the first point at 80 % of the depth
        while 0 < j < len(z) - 1 and r[j] < hi:
            j += side
        a_, b_ = sorted((i0, j))
        ang, fit = _fit_flank(z[a_:b_ + 1], r[a_:b_ + 1], lo, hi)
        angs.append(ang)
        if fit is not None:
            a, b = fit
            ch.lines([((a * rv + b, s * rv), (a * r_crest + b, s * r_crest))], color="#b03030", width=2.0,
                     dz=1.3)
            rm = rv + 0.55 * depth
            ch.text(a * rm + b + side * ch.px(10), s * rm, f"{ang:.1f}\u00b0", size=14, color="#b03030",
                    halign="left" if side > 0 else "right", bold=True)
    if all(a is not None for a in angs):
        ftxt = f"flanks {angs[0]:.1f}\u00b0 + {angs[1]:.1f}\u00b0 = {angs[0] + angs[1]:.1f}\u00b0 included"
        ch.text(zr, s * (r_crest + 0.28 * h), ftxt, size=13, color="#b03030", bold=True)
        return ftxt
    return None


def ramp_view(result, spec, index: int) -> View:
    """Lathe: the section near C0 (``section_angle``) over a ``ramp`` check with the measured root
    radius (over all angles) and the expected ramp."""
    from cutsim.reports import measure as M

    (za, zb), (ra, rb) = spec["z"], spec["radius"]
    zs, rs = M.root_radius_profile(result.part, za, zb, spec.get("step", 0.25))
    sb = result.stock.bounding_box()
    rtop = max(abs(v) for v in (sb[0], sb[1], sb[3], sb[4]))
    lo = min(ra, rb, float(np.nanmin(rs)) if np.any(np.isfinite(rs)) else ra)
    span = abs(zb - za)
    zlo, zhi = min(za, zb) - 0.3 * span, max(za, zb) + 0.3 * span
    v0, v1 = lo - 0.25 * (rtop - lo) - 0.2, rtop + 0.25 * (rtop - lo) + 0.2
    p = _plotter()
    ch = _Chart(p, (zlo, zhi, v0, v1), margins=(90, 90, 70, 85))
    phi = section_angle(result)
    part, stock, removed = _lathe_sections(result, ch.box, phi)
    ch.fill(part, PART_COLOR)
    ch.fill(removed, REMOVED_COLOR, dz=0.1)
    ch.lines([np.vstack([q, q[:1]]) for q in part], color="#333333", width=1.0, dz=0.5)
    ch.axes("Z mm", "radius mm", v2=lambda x: 2 * x, v2title="\u00d8 mm")
    ch.lines([((za, ra), (zb, rb))], color="#2a8a3a", width=7.0, dz=1.2)
    ok = np.isfinite(rs)
    ch.lines([np.column_stack([zs[ok], rs[ok]])], color="#1f5fa8", width=2.5, dz=1.3)
    dev = rs[ok] - (ra + (zs[ok] - za) * (rb - ra) / (zb - za))
    worst = float(dev[np.argmax(np.abs(dev))]) if len(dev) else float("nan")
    txt = (f"expected r {_num(ra)} to {_num(rb)} over Z {_num(za, 2)} \u2026 {_num(zb, 2)}; measured root "
           f"{_num(float(rs[0]))} to {_num(float(rs[-1]))}, worst {_num(worst)} (\u00b1{spec['tolerance']:g})")
    ch.text(ch.box[0] + ch.px(8), ch.box[3] - ch.px(8), txt, size=13, halign="left", valign="top", bold=True)
    ch.title(f"{spec['name']}: ramp at C{_num(phi, 2)}\u00b0 (+X) and the root radius over all angles")
    ch.legend([("root radius (all angles)", "#1f5fa8"), ("expected ramp", "#2a8a3a"), (f"part at C{_num(phi, 2)}\u00b0", PART_COLOR)])
    return View(f"ramp-{index}.png", f"Ramp check \u201c{spec['name']}\u201d: section at C{_num(phi, 2)}\u00b0, the root radius "
                "measured over all angles (blue) and the ramp the check expects (wide green line).",
                p, ch.ticks, [txt], pixel=ch.pixel)


def top_view(result) -> View:
    """Mill: the part from above, coloured over the cut depth range (a colour per floor)."""
    pv = _pv()
    v, f = solid_arrays(result.part)
    up, levels = floor_levels(v, f)
    sb = result.stock.bounding_box()
    ztop = float(sb[5])
    zbot = float(levels.min()) if len(levels) else float(sb[2])
    part = _polydata(v, f)
    p = _plotter(lighting="none")
    ch = _Chart(p, (sb[0] - 0.04 * (sb[3] - sb[0]), sb[3] + 0.04 * (sb[3] - sb[0]),
                    sb[1] - 0.04 * (sb[4] - sb[1]), sb[4] + 0.04 * (sb[4] - sb[1])),
                margins=(85, 210, 70, 60), plane_z=ztop + 5.0)
    zc = v[f][:, :, 2].mean(axis=1)
    notes = []
    if 0 < len(levels) <= MAX_FLOORS:
        colors = _floor_colors(levels, ztop, zbot)
        idx = _face_floor_index(v, f, levels)
        rgb = np.array(colors)[idx]
        rgb[~up] = _rgb(WALL_COLOR)
        part.cell_data["rgb"] = (rgb * 255).astype(np.uint8)
        p.add_mesh(part, scalars="rgb", rgb=True, lighting=False, reset_camera=False)
        y = HEIGHT - 80
        ch.text(*ch.world(WIDTH - 195, y), "flat faces: Z mm, area", size=13, halign="left", bold=True)
        for z, c in zip(levels, colors):
            y -= 28
            area = _floor_area(v, f, up, z)
            lab = f"{_num(float(z))}   {area:,.0f} mm\u00b2"
            a, b = ch.world(WIDTH - 195, y - 9)
            c2, d2 = ch.world(WIDTH - 177, y + 9)
            ch.fill([np.array([(a, b), (c2, b), (c2, d2), (a, d2)])], c, dz=3.0)
            ch.text(*ch.world(WIDTH - 170, y), lab, size=13, halign="left")
            notes.append(f"floor Z {_num(float(z))}")
    else:
        part.cell_data["Z mm"] = zc
        p.add_mesh(part, scalars="Z mm", cmap="viridis", clim=(zbot, ztop), lighting=False, reset_camera=False,
                   scalar_bar_args={"color": "black", "vertical": True, "fmt": "%.2f", "position_x": 0.83,
                                    "position_y": 0.15, "height": 0.7, "width": 0.06, "title": "Z mm"})
        pts = _mesh(result.part)
        try:
            cont = pts.slice_along_axis(n=8, axis="z", bounds=(0, 0, 0, 0, zbot + 1e-3, ztop - 1e-3))
            p.add_mesh(cont, color="black", line_width=1.0, reset_camera=False)
        except Exception:  # noqa: BLE001 - contour lines are a help, not a must
            pass
    st = _stock_outline(result)
    p.add_mesh(st, color="#555555", line_width=1.0, reset_camera=False)
    ch.axes("X mm", "Y mm", grid=False, limits=(sb[0], sb[3], sb[1], sb[4]))
    ch.title(f"{result.report.get('program', '')}: top view, colour = Z over the cut depth, stock top "
             f"{_num(ztop, 2)} to deepest floor {_num(zbot, 2)}")
    del pv
    return View("top.png", "Top view: every face coloured by its height over the cut depth range (stock top to "
                "the deepest floor), one colour per distinct floor; walls light grey.", p, ch.ticks, notes,
                pixel=ch.pixel, mesh=part)


def _floor_area(v, f, up, z) -> float:
    t = v[f]
    sel = up & (np.round(t[:, :, 2].mean(axis=1), 3) == z)
    n = np.cross(t[sel, 1] - t[sel, 0], t[sel, 2] - t[sel, 0])
    return 0.5 * float(np.linalg.norm(n, axis=1).sum())


# ------------------------------------------------------------------------------------------------
def views(result, progress=None):
    """The views of ``result`` as :class:`View` objects, rendered one by one (a generator, so only
    one plotter is open at a time). ``progress(stage, i, n)`` is called as they are made."""
    from cutsim.reports.measure import load_solid

    checks = result.setup.checks
    lathe = result.setup.machine.kind == "lathe"
    makers = [iso_view]
    if lathe:
        makers.append(section_view)
        for k, spec in enumerate([c for c in checks if c["kind"] == "thread"], 1):
            makers.append(lambda r, s=spec, k=k: thread_view(r, s, k))
        for k, spec in enumerate([c for c in checks if c["kind"] == "ramp"], 1):
            makers.append(lambda r, s=spec, k=k: ramp_view(r, s, k))
    else:
        makers.append(top_view)
    designs = [c for c in checks if c["kind"] == "design"]
    if designs:
        makers.append(lambda r: deviation_view(r, load_solid(designs[0]["path"]), designs[0], progress))
    n = len(makers)
    for i, make in enumerate(makers):
        if progress:
            progress("images", i, n)
        yield make(result)
    if progress:
        progress("images", n, n)


def render_images(result, progress=None, captions: dict | None = None) -> dict[str, bytes]:
    """PNG views of ``result``: {file name: bytes} (see the module docstring). ``captions``, when
    given, is filled with {file name: caption}."""
    out = {}
    for view in views(result, progress):
        out[view.name] = view.png()
        if captions is not None:
            captions[view.name] = view.caption
    return out

