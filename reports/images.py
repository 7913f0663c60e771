"""Off-screen PNG views of a result (``cutsim simulate ... --images``). pyvista is imported inside
the functions only, so the rest of cutsim works without it.

Every view is WIDTH x HEIGHT pixels on white. The 2D views (sections, the top view) are drawn in
parallel projection at one scale in both directions (mm are mm), framed by rulers whose ticks are
round numbers in true workpiece coordinates (a part at Z-30..0 reads -30..0, a thread at radius
10.5..13.5 reads 10.5..13.5); their labels are text actors of the plotter (:class:`View`).

Lathe:
- ``iso.png``: isometric view of the part, the stock's outline and axes with round ticks;
- ``section.png``: the full-length half-section at C0 (the half-plane through +X): part in grey,
  the material removed from the stock in orange, the stock outline in red; Z along the bottom,
  the radius on the left and the diameter on the right;
- ``thread-N.png`` for the N-th ``thread`` check: two and a half pitches around the middle of its
  range at C0 with the measured root and crest diameters, the pitch and both flank angles;
- ``ramp-N.png`` for the N-th ``ramp`` check (lead-in, runout): the section at C0 over the ramp with
  the root radius measured over all angles and the ramp the check expects.

Mill:
- ``top.png``: the part from above coloured over the cut depth range (stock top to deepest floor),
  one colour per distinct floor (a legend lists their Z), continuous with contour lines when the
  part has more than MAX_FLOORS flat levels;
- ``iso.png``: isometric view with floors in the same colours as the top view and walls grey;
- with a design check, ``deviation.png``: each face of the part coloured by its signed distance
  to the design (cell data; blue = gouge, red = excess) on a diverging scale symmetric about 0,
  clipped to +-DEV_K x tolerance, the tolerance band neutral; the worst gouge and excess labelled.
"""
from __future__ import annotations

import io
import math
from dataclasses import dataclass, field

import numpy as np

WIDTH, HEIGHT = 1024, 768
MAX_FLOORS = 12  # more flat levels than this: continuous colours with contour lines
DEV_K = 3.0  # the deviation scale runs over +-DEV_K x the tolerance
PART_COLOR = "#b8c4cc"
REMOVED_COLOR = "#f5c48a"
STOCK_COLOR = "#c0301c"
WALL_COLOR = "#c9ced3"


@dataclass
class View:
    """One rendered view: the file name, a caption for report.html, the plotter (off-screen, not yet
    closed) and the tick values of its rulers in workpiece coordinates ({axis: [values]})."""
    name: str
    caption: str
    plotter: object
    ticks: dict = field(default_factory=dict)
    notes: list = field(default_factory=list)  # annotation texts (measured values)
    pixel: object = None  # 2D views: (u, v) in mm -> (row, column) of the PNG
    mesh: object = None  # the coloured part (pyvista PolyData) where the colours carry data

    def png(self) -> bytes:
        return _png(self.plotter)


# ------------------------------------------------------------------------------------------------
# pyvista plumbing
# ------------------------------------------------------------------------------------------------
def _pv():
    import pyvista as pv

    pv.OFF_SCREEN = True
    try:  # VTK's own log says "bad X server connection" on a machine without a display: not ours to show
        from vtkmodules.vtkCommonCore import vtkLogger

        vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)
    except ImportError:  # pragma: no cover - older VTK without the logger
        pass
    return pv


def _polydata(verts: np.ndarray, faces: np.ndarray):
    pv = _pv()
    f = np.hstack([np.full((len(faces), 1), 3, dtype=np.int64), faces.astype(np.int64)]).ravel()
    return pv.PolyData(np.asarray(verts, dtype=np.float64), f)


def _arrays(man) -> tuple[np.ndarray, np.ndarray]:
    m = man.to_mesh()
    return np.asarray(m.vert_properties, dtype=np.float64)[:, :3], np.asarray(m.tri_verts, dtype=np.int64)


def _mesh(man):
    return _polydata(*_arrays(man))


def _plotter(lighting="light kit"):
    pv = _pv()
    p = pv.Plotter(off_screen=True, window_size=(WIDTH, HEIGHT), lighting=lighting)
    p.set_background("white")
    return p


def _png(p) -> bytes:
    p.renderer.ResetCameraClippingRange()
    img = p.screenshot(None, return_img=True)
    p.close()
    from PIL import Image

    buf = io.BytesIO()
    Image.fromarray(np.asarray(img)).save(buf, format="PNG", optimize=False)
    return buf.getvalue()


def _rgb(color) -> tuple[float, float, float]:
    from matplotlib.colors import to_rgb

    return tuple(float(c) for c in to_rgb(color))


def text_actors(plotter) -> list[tuple[str, tuple[float, float, float]]]:
    """(text, world position) of every world-anchored text actor of ``plotter`` (tick labels and
    annotations), in the order they were added."""
    from vtkmodules.vtkRenderingCore import vtkTextActor

    out = []
    for a in plotter.renderer.actors.values():
        if isinstance(a, vtkTextActor) and a.GetPositionCoordinate().GetCoordinateSystemAsString() == "World":
            out.append((a.GetInput(), tuple(a.GetPositionCoordinate().GetValue())))
    return out


def nice_step(span: float, n: int = 6) -> float:
    """A round step (1, 2, 2.5 or 5 x 10^k) giving about ``n`` intervals over ``span``."""
    if not span > 0:
        return 1.0
    raw = span / max(1, n)
    k = 10.0 ** math.floor(math.log10(raw))
    for m in (1.0, 2.0, 2.5, 5.0, 10.0):
        if m * k >= raw * 0.999:
            return m * k
    return 10.0 * k  # pragma: no cover


def nice_ticks(lo: float, hi: float, n: int = 6) -> list[float]:
    """Round tick values inside [lo, hi] (about ``n`` intervals)."""
    step = nice_step(hi - lo, n)
    first = math.ceil(lo / step - 1e-9) * step
    out = []
    v = first
    while v <= hi + 1e-9 * step:
        out.append(0.0 if abs(v) < 1e-9 * step else round(v, 10))
        v += step
    return out


def _fmt_tick(v: float, step: float) -> str:
    nd = max(0, -int(math.floor(math.log10(step) + 1e-9))) if step < 1 else 0
    if step < 1 and abs(step * 10 ** nd - round(step * 10 ** nd)) > 1e-6:
        nd += 1
    s = f"{v:.{nd}f}"
    return s.replace("-", "\u2212") if v < 0 else s


def _num(v: float, nd: int = 3) -> str:
    """A measured value for a label, with a true minus sign."""
    s = f"{v:.{nd}f}"
    return s.replace("-", "\u2212")


class _Chart:
    """A 2D drawing in the plane z = ``plane_z`` seen from +z in parallel projection: world (u, v)
    is (x, y), one scale for both, the data box fitted into the window inside pixel margins and
    widened to fill it, rulers with round ticks along the bottom and the left (and optionally a
    second scale on the right)."""

    def __init__(self, p, box, margins=(95, 95, 70, 80), plane_z: float = 0.0, anchor_v0: bool = False,
                 widen_v: bool = True):
        self.p = p
        self.z = plane_z
        u0, u1, v0, v1 = box
        ml, mr, mb, mt = margins
        aw, ah = WIDTH - ml - mr, HEIGHT - mb - mt
        s = min(aw / max(u1 - u0, 1e-9), ah / max(v1 - v0, 1e-9))
        du, dv = (aw / s - (u1 - u0)) / 2, (ah / s - (v1 - v0)) / 2
        if not widen_v:  # a long slender part: the frame hugs it, the page stays white around it
            dv = 0.0
        if anchor_v0:  # keep v0 (the axis of a lathe section) at the bottom: widen upwards only
            v0, v1 = v0 + dv, v1 + dv
        self.box = (u0 - du, u1 + du, v0 - dv, v1 + dv)
        self.s = s
        uc = (u0 + u1) / 2 - (ml + aw / 2 - WIDTH / 2) / s
        vc = (self.box[2] + self.box[3]) / 2 - (mb + ah / 2 - HEIGHT / 2) / s
        p.camera_position = [(uc, vc, plane_z + 1000.0), (uc, vc, plane_z), (0.0, 1.0, 0.0)]
        p.enable_parallel_projection()
        p.camera.parallel_scale = HEIGHT / (2 * s)
        self.ticks = {}
        self.n_text = 0
        self.pix = (uc, vc)

    def pixel(self, u: float, v: float) -> tuple[int, int]:
        """(row, column) in the PNG of the world point (u, v)."""
        col = WIDTH / 2 + (u - self.pix[0]) * self.s
        row = HEIGHT / 2 - (v - self.pix[1]) * self.s
        return int(round(row)), int(round(col))

    def world(self, x_px: float, y_px: float) -> tuple[float, float]:
        """World (u, v) of the pixel (x_px, y_px) counted from the bottom left."""
        return self.pix[0] + (x_px - WIDTH / 2) / self.s, self.pix[1] + (y_px - HEIGHT / 2) / self.s

    def px(self, n: float) -> float:
        """``n`` pixels in mm."""
        return n / self.s

    def pt(self, u, v, dz: float = 0.0):
        return (float(u), float(v), self.z + dz)

    def text(self, u, v, s, size=14, color="black", halign="center", valign="center", bold=False, dz=2.0):
        from vtkmodules.vtkRenderingCore import vtkTextActor

        a = vtkTextActor()
        a.SetInput(s)
        tp = a.GetTextProperty()
        tp.SetFontSize(size)
        tp.SetColor(*_rgb(color))
        tp.SetFontFamilyToArial()
        tp.SetBold(bold)
        if bold:  # annotations stay readable over the drawing
            tp.SetBackgroundColor(1.0, 1.0, 1.0)
            tp.SetBackgroundOpacity(0.85)
        {"left": tp.SetJustificationToLeft, "center": tp.SetJustificationToCentered,
         "right": tp.SetJustificationToRight}[halign]()
        {"top": tp.SetVerticalJustificationToTop, "center": tp.SetVerticalJustificationToCentered,
         "bottom": tp.SetVerticalJustificationToBottom}[valign]()
        c = a.GetPositionCoordinate()
        c.SetCoordinateSystemToWorld()
        c.SetValue(*self.pt(u, v, dz))
        self.n_text += 1
        self.p.add_actor(a, reset_camera=False, name=f"text-{self.n_text}")
        return a

    def lines(self, segs, color="black", width=1.0, dz=1.0, dashed=False):
        """Line segments ((u0, v0), (u1, v1)) (or polylines given as (n, 2) arrays)."""
        pv = _pv()
        pieces = []
        for seg in segs:
            a = np.asarray(seg, dtype=float)
            for k in range(len(a) - 1):
                pieces.append((a[k], a[k + 1]))
        if dashed:
            dash = self.px(7.0)
            out = []
            for a, b in pieces:
                L = float(np.hypot(*(b - a)))
                n = max(1, int(L / dash))
                for k in range(0, n, 2):
                    out.append((a + (b - a) * k / n, a + (b - a) * min(n, k + 1) / n))
            pieces = out
        if not pieces:
            return
        pts = np.array([[*q, self.z + dz] for ab in pieces for q in ab], dtype=float)
        ln = np.hstack([np.full((len(pieces), 1), 2), np.arange(2 * len(pieces)).reshape(-1, 2)]).ravel()
        self.p.add_mesh(pv.PolyData(pts, lines=ln), color=color, line_width=width, lighting=False,
                        reset_camera=False)

    def fill(self, polys, color, dz=0.0, opacity=1.0):
        """Fill the region of closed polygons (u, v) (holes clockwise, as manifold3d gives them)."""
        from manifold3d import CrossSection, triangulate

        polys = [np.asarray(q, dtype=float) for q in polys if len(q) >= 3]
        if not polys:
            return
        cs = CrossSection(polys)
        polys = [np.asarray(q, dtype=float) for q in cs.to_polygons() if len(q) >= 3]
        if not polys:
            return
        tri = np.asarray(triangulate(polys), dtype=np.int64).reshape(-1, 3)
        v = np.concatenate(polys)
        pts = np.column_stack([v, np.full(len(v), self.z + dz)])
        self.p.add_mesh(_polydata(pts, tri), color=color, lighting=False, opacity=opacity, reset_camera=False)

    def marker(self, u, v, color="black", size_px=5.0, dz=1.5):
        r = self.px(size_px)
        self.lines([((u - r, v), (u + r, v)), ((u, v - r), (u, v + r))], color=color, width=2.5, dz=dz)

    def axes(self, utitle, vtitle, v2=None, v2title=None, n=8, grid=True):
        """Frame, ticks and labels. ``v2``: a function mapping v to a second scale on the right."""
        u0, u1, v0, v1 = self.box
        nu = max(3, int(round(n * (u1 - u0) / max(u1 - u0, v1 - v0))))
        nv = max(3, int(round(n * (v1 - v0) / max(u1 - u0, v1 - v0))))
        tu, tv = nice_ticks(u0, u1, nu), nice_ticks(v0, v1, nv)
        su = tu[1] - tu[0] if len(tu) > 1 else 1.0
        sv = tv[1] - tv[0] if len(tv) > 1 else 1.0
        self.ticks = {utitle: tu, vtitle: tv}
        if grid:
            self.lines([((u, v0), (u, v1)) for u in tu] + [((u0, v), (u1, v)) for v in tv], color="#e2e2e2",
                       width=1.0, dz=-0.5)
        self.lines([((u0, v0), (u1, v0), (u1, v1), (u0, v1), (u0, v0))], color="black", width=1.2, dz=1.0)
        t = self.px(6)
        self.lines([((u, v0), (u, v0 - t)) for u in tu] + [((u0, v), (u0 - t, v)) for v in tv], width=1.2)
        for u in tu:
            self.text(u, v0 - self.px(9), _fmt_tick(u, su), size=13, valign="top")
        for v in tv:
            self.text(u0 - self.px(9), v, _fmt_tick(v, sv), size=13, halign="right")
        self.text((u0 + u1) / 2, v0 - self.px(34), utitle, size=14, valign="top", bold=True)
        self.text(u0 - self.px(9), v1 + self.px(12), vtitle, size=14, halign="left", valign="bottom", bold=True)
        if v2 is not None:
            self.lines([((u1, v), (u1 + t, v)) for v in tv], width=1.2)
            vals = [v2(v) for v in tv]
            self.ticks[v2title] = vals
            for v, w in zip(tv, vals):
                self.text(u1 + self.px(9), v, _fmt_tick(w, 2 * sv), size=13, halign="left")
            self.text(u1 + self.px(9), v1 + self.px(12), v2title, size=14, halign="right", valign="bottom",
                      bold=True)

    def title(self, s):
        self.p.add_text(s, position=(12, HEIGHT - 28), font_size=11, color="black")

    def legend(self, items, y_px: float = HEIGHT - 44):
        """Colour swatches with labels along the top right: [(label, color)]."""
        widths = [7.0 * len(label) + 22 for label, _ in items]
        x = WIDTH - 14 - sum(widths) - 16 * max(0, len(items) - 1)
        for (label, color), w in zip(items, widths):
            a, b = self.world(x, y_px - 7)
            c, d = self.world(x + 14, y_px + 7)
            self.fill([np.array([(a, b), (c, b), (c, d), (a, d)])], color, dz=3.0)
            self.lines([((a, b), (c, b), (c, d), (a, d), (a, b))], color="#444444", dz=3.1)
            self.text(*self.world(x + 20, y_px), label, size=13, halign="left")
            x += w + 16


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
def _lathe_sections(result, window=None):
    """(part, stock, removed) half-sections at C0 as (z, r) polygon lists, clipped to ``window``."""
    from cutsim.reports import measure as M

    part = _cs(_swap(M.half_plane_section(result.part, 0.0)))
    stock = _cs(_swap(M.half_plane_section(result.stock, 0.0)))
    removed = stock - part
    if window is not None:
        w = _rect(*window)
        part, stock, removed = part ^ w, stock ^ w, removed ^ w
    return _polys(part), _polys(stock), _polys(removed)


def section_view(result) -> View:
    """Lathe: the full-length half-section at C0 in true coordinates (Z across, radius up)."""
    p = _plotter()
    sb = result.stock.bounding_box()
    pb = result.part.bounding_box()
    z0, z1 = min(sb[2], pb[2]), max(sb[5], pb[5])
    rmax = max(abs(v) for v in (sb[0], sb[1], sb[3], sb[4], pb[0], pb[1], pb[3], pb[4]))
    mz = 0.06 * (z1 - z0) + 0.5
    s_est = (WIDTH - 160) / (z1 - z0 + 2 * mz)  # px per mm when the length fills the width
    mr = 0.12 * rmax + 0.5 + 64.0 / s_est  # room above the part for the checks' brackets
    ch = _Chart(p, (z0 - mz, z1 + mz, 0.0, rmax + mr), margins=(80, 80, 70, 85), anchor_v0=True,
                widen_v=False)
    part, stock, removed = _lathe_sections(result)
    ch.fill(part, PART_COLOR)
    ch.fill(removed, REMOVED_COLOR, dz=0.1)
    ch.lines(part, color="#333333", width=1.0, dz=0.5)
    ch.lines([np.vstack([q, q[:1]]) for q in stock], color=STOCK_COLOR, width=2.0, dz=0.8)
    u0, u1 = ch.box[:2]
    ch.lines([((u0, 0.0), (u1, 0.0))], color="#555555", width=1.0, dashed=True, dz=0.9)
    ch.axes("Z mm", "radius mm", v2=lambda r: 2 * r, v2title="\u00d8 mm")
    _mark_checks(ch, result)
    ch.title(f"{result.report.get('program', '')}: half-section at C0 (+X), Z {_num(z0, 2)} \u2026 {_num(z1, 2)}")
    ch.legend([("part", PART_COLOR), ("removed", REMOVED_COLOR), ("stock outline", STOCK_COLOR)])
    return View("section.png", "Half-section at C0 (the half-plane through +X) in workpiece coordinates: "
                "part grey, removed material orange, stock outline red; radius left, diameter right.",
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
    """Lathe: 2.5 pitches of the ``thread`` check ``spec`` around the middle of its range at C0,
    with measured root and crest diameters, pitch and flank angles."""
    from cutsim.reports import measure as M

    zlo, zhi = spec["z"]
    m = M.measure_thread(result.part, zlo, zhi, spec.get("angles", 36))
    pitch = m["pitch"] or spec["lead"] / max(1, spec["starts"])
    zc = 0.5 * (zlo + zhi)
    za, zb = zc - 1.25 * pitch, zc + 1.25 * pitch
    z, r = M.outer_profile(result.part, 0.0, za - pitch, zb + pitch, step=pitch / 400.0)
    ok = np.isfinite(r)
    z, r = z[ok], r[ok]
    inwin = (z >= za) & (z <= zb)
    r_crest = float(r[inwin].max()) if np.any(inwin) else float(np.nanmax(r))
    roots = M.groove_roots(z, r)
    r_root_sec = float(roots[:, 1].min()) if len(roots) else float(r.min())
    h = max(r_crest - r_root_sec, 0.1 * pitch)
    v0, v1 = r_root_sec - 0.55 * h, r_crest + 0.45 * h
    p = _plotter()
    ch = _Chart(p, (za, zb, v0, v1), margins=(90, 90, 70, 85))
    win = ch.box
    part, stock, removed = _lathe_sections(result, win)
    ch.fill(part, PART_COLOR)
    ch.fill(removed, REMOVED_COLOR, dz=0.1)
    ch.lines([np.vstack([q, q[:1]]) for q in part], color="#333333", width=1.2, dz=0.5)
    ch.axes("Z mm", "radius mm", v2=lambda x: 2 * x, v2title="\u00d8 mm", grid=True)
    u0, u1 = win[0], win[1]
    notes = []
    # root and crest levels
    d_root = m["root_diameter"]
    rr = d_root / 2 if d_root else r_root_sec
    ch.lines([((u0, rr), (u1, rr))], color="#1f5fa8", width=1.5, dashed=True, dz=1.0)
    ch.lines([((u0, r_crest), (u1, r_crest))], color="#2a8a3a", width=1.5, dashed=True, dz=1.0)
    root_txt = f"root \u00d8 {_num(d_root)}" if d_root else "root: not measured"
    if d_root and m["root_diameter_min"] is not None:
        root_txt += f"  ({_num(m['root_diameter_min'])} \u2026 {_num(m['root_diameter_max'])} over all angles)"
    if spec.get("root_diameter") is not None:
        root_txt += f"  check {_num(spec['root_diameter'])} \u00b1{spec['tolerance']:g}"
    crest_txt = f"crest \u00d8 {_num(2 * r_crest)}"
    ch.text(u0 + ch.px(8), rr - ch.px(6), root_txt, size=13, color="#1f5fa8", halign="left", valign="top",
            bold=True)
    ch.text(u0 + ch.px(8), r_crest + ch.px(6), crest_txt, size=13, color="#2a8a3a", halign="left",
            valign="bottom", bold=True)
    notes += [root_txt, crest_txt]
    # roots in the window, pitch between the two nearest the middle
    rts = roots[(roots[:, 0] >= u0) & (roots[:, 0] <= u1)] if len(roots) else roots
    for zr, rv in rts:
        ch.marker(zr, rv, color="#1f5fa8")
    if len(rts) >= 2:
        k = int(np.argmin(np.abs(rts[:, 0] - zc)))
        k2 = k + 1 if k + 1 < len(rts) else k - 1
        a_, b_ = sorted((float(rts[k, 0]), float(rts[k2, 0])))
        vy = r_root_sec - 0.3 * h
        t = ch.px(6)
        ch.lines([((a_, vy), (b_, vy)), ((a_, vy - t), (a_, vy + t)), ((b_, vy - t), (b_, vy + t)),
                  ((a_, vy + t), (a_, rts[k, 1])), ((b_, vy + t), (b_, rts[k2, 1]))], color="black", width=1.3,
                 dz=1.2)
        ptxt = f"P {_num(b_ - a_)} here, {_num(pitch)} median  (lead {_num(m['lead']) if m['lead'] else '?'})"
        ch.text((a_ + b_) / 2, vy - ch.px(8), ptxt, size=13, valign="top", bold=True)
        notes.append(ptxt)
    # flank angles of the groove nearest the middle
    if len(rts):
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
                ch.lines([((a * rv + b, rv), (a * r_crest + b, r_crest))], color="#b03030", width=2.0, dz=1.3)
                rm = rv + 0.55 * depth
                ch.text(a * rm + b + side * ch.px(10), rm, f"{ang:.1f}\u00b0", size=14, color="#b03030",
                        halign="left" if side > 0 else "right", bold=True)
        if all(a is not None for a in angs):
            ftxt = f"flanks {angs[0]:.1f}\u00b0 + {angs[1]:.1f}\u00b0 = {angs[0] + angs[1]:.1f}\u00b0 included"
            ch.text(zr, r_crest + 0.28 * h, ftxt, size=13, color="#b03030", bold=True)
            notes.append(ftxt)
    name = spec["name"]
    ch.title(f"{name}: tooth detail at C0 (+X); checked Z {_num(zlo, 2)} \u2026 {_num(zhi, 2)}, "
             f"{m['starts'] or '?'} start(s), {m['hand'] or '?'} hand")
    ch.legend([("part", PART_COLOR), ("removed", REMOVED_COLOR)])
    return View(f"thread-{index}.png", f"Thread check \u201c{name}\u201d: two and a half pitches at C0 around "
                f"Z {_num(zc, 2)} with the measured root and crest diameters, pitch and flank angles.",
                p, ch.ticks, notes, pixel=ch.pixel)


def ramp_view(result, spec, index: int) -> View:
    """Lathe: the section at C0 over a ``ramp`` check with the measured root radius (over all
    angles) and the expected ramp."""
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
    part, stock, removed = _lathe_sections(result, ch.box)
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
    ch.title(f"{spec['name']}: ramp at C0 (+X) and the root radius over all angles")
    ch.legend([("root radius (all angles)", "#1f5fa8"), ("expected ramp", "#2a8a3a"), ("part at C0", PART_COLOR)])
    return View(f"ramp-{index}.png", f"Ramp check \u201c{spec['name']}\u201d: section at C0, the root radius "
                "measured over all angles (blue) and the ramp the check expects (wide green line).",
                p, ch.ticks, [txt], pixel=ch.pixel)


# ------------------------------------------------------------------------------------------------
# mill
# ------------------------------------------------------------------------------------------------
def floor_levels(v: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per face: whether it faces up (a floor or the top) and the distinct Z of the floors (to
    0.001 mm, from the highest down)."""
    t = v[f]
    n = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
    ln = np.linalg.norm(n, axis=1)
    up = (ln > 0) & (n[:, 2] > 0.999 * np.where(ln > 0, ln, 1.0))
    zc = np.round(t[:, :, 2].mean(axis=1), 3)
    return up, np.unique(zc[up])[::-1]


def _floor_colors(levels: np.ndarray, ztop: float, zbot: float):
    import matplotlib

    cmap = matplotlib.colormaps["viridis"]
    span = max(ztop - zbot, 1e-9)
    return [cmap(0.08 + 0.84 * (float(z) - zbot) / span)[:3] for z in levels]


def _face_floor_index(v, f, levels):
    zc = np.round(v[f][:, :, 2].mean(axis=1), 3)
    idx = np.searchsorted(-levels, -zc)
    idx = np.clip(idx, 0, max(0, len(levels) - 1))
    return idx


def top_view(result) -> View:
    """Mill: the part from above, coloured over the cut depth range (a colour per floor)."""
    pv = _pv()
    v, f = _arrays(result.part)
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
    ch.axes("X mm", "Y mm", grid=False)
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


def _stock_outline(result):
    return _mesh(result.stock).extract_feature_edges(feature_angle=30.0, boundary_edges=False,
                                                     non_manifold_edges=False, manifold_edges=False)


def _iso_axes(p, b, z_labels: int = 3):
    """Axes with round ticks: the bounds widened to multiples of a round step."""
    def rng(lo, hi, n):
        step = nice_step(hi - lo, n)
        a, c = math.floor(lo / step + 1e-9) * step, math.ceil(hi / step - 1e-9) * step
        return a, c, int(round((c - a) / step)) + 1

    x0, x1, nx = rng(b[0], b[3], 5)
    y0, y1, ny = rng(b[1], b[4], 5)
    z0, z1, nz = rng(b[2], b[5], z_labels)
    p.show_bounds(bounds=(x0, x1, y0, y1, z0, z1), grid=False, location="outer", color="black", font_size=10,
                  xtitle="X mm", ytitle="Y mm", ztitle="Z mm", fmt="%.4g", n_xlabels=nx, n_ylabels=ny,
                  n_zlabels=nz, use_3d_text=False)
    return {"X mm": [float(v) for v in np.linspace(x0, x1, nx)], "Y mm": [float(v) for v in np.linspace(y0, y1, ny)],
            "Z mm": [float(v) for v in np.linspace(z0, z1, nz)]}


def _iso(p, result, caption, name="iso.png", notes=None, zoom=0.95) -> View:
    p.add_mesh(_stock_outline(result), color="#555555", line_width=1.0, opacity=0.6, reset_camera=False)
    b = result.stock.bounding_box()
    ticks = _iso_axes(p, b)
    if result.setup.machine.kind == "lathe":
        # as the part sits in the lathe: the spindle axis (Z) across, X up, seen from the operator's
        # side, Z growing to the right (the chuck on the left), a little from above and from the face end
        c = np.array([(b[0] + b[3]) / 2, (b[1] + b[4]) / 2, (b[2] + b[5]) / 2])
        d = np.array([0.45, 1.0, 0.35])
        p.camera_position = [tuple(c + 1000.0 * d / np.linalg.norm(d)), tuple(c), (1.0, 0.0, 0.0)]
    else:
        p.view_isometric()
    p.reset_camera()
    p.camera.zoom(zoom)
    return View(name, caption, p, ticks, notes or [])


def iso_view(result) -> View:
    """Isometric view; on a mill part the floors take their top-view colours, walls grey."""
    p = _plotter()
    v, f = _arrays(result.part)
    part = _polydata(v, f)
    if result.setup.machine.kind != "lathe":
        up, levels = floor_levels(v, f)
        sb = result.stock.bounding_box()
        if 0 < len(levels) <= MAX_FLOORS:
            colors = np.array(_floor_colors(levels, float(sb[5]), float(levels.min())))
            rgb = colors[_face_floor_index(v, f, levels)]
        else:
            import matplotlib

            zc = v[f][:, :, 2].mean(axis=1)
            span = max(float(sb[5]) - float(zc.min()), 1e-9)
            rgb = np.asarray(matplotlib.colormaps["viridis"](0.08 + 0.84 * (zc - zc.min()) / span))[:, :3]
        rgb[~up] = _rgb(WALL_COLOR)
        part.cell_data["rgb"] = (rgb * 255).astype(np.uint8)
        p.add_mesh(part, scalars="rgb", rgb=True, smooth_shading=False, specular=0.15, ambient=0.25,
                   reset_camera=False)
        cap = "Isometric view: floors in their top-view colours, walls grey; the stock's outline in grey."
    else:
        p.add_mesh(part, color=PART_COLOR, smooth_shading=False, specular=0.3, ambient=0.3, reset_camera=False)
        cap = "Isometric view of the part with the stock's outline."
    return _iso(p, result, cap)


# ------------------------------------------------------------------------------------------------
# deviation
# ------------------------------------------------------------------------------------------------
def face_deviation(part, design, progress=None, chunk: int = 2000
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Part mesh (vertices, faces), per face the signed distance from its centroid to the design
    surface (positive outside the design: excess; negative inside: gouge) and the centroids.
    Computed in chunks of ``chunk`` faces with ``progress("deviation", i, n)`` (faces done)."""
    from cutsim.reports.measure import _point_triangle_distance

    pv_, pf = _arrays(part)
    dv, df = _arrays(design)
    tri = dv[df]
    cen = pv_[pf].mean(axis=1)
    n = len(cen)
    d, q, k = np.zeros(n), np.zeros((n, 3)), np.zeros(n, dtype=np.int64)
    for i in range(0, n, chunk):
        if progress:
            progress("deviation", i, n)
        if len(tri) * min(chunk, n - i) > 500_000:
            d[i:i + chunk], q[i:i + chunk], k[i:i + chunk] = _nearest_on_triangles(cen[i:i + chunk], tri)
        else:
            d[i:i + chunk], q[i:i + chunk], k[i:i + chunk] = _point_triangle_distance(cen[i:i + chunk], tri)
    if progress:
        progress("deviation", n, n)
    nrm = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    side = np.einsum("ij,ij->i", cen - q, nrm[k])
    return pv_, pf, np.where(side < 0, -d, d), cen


def _nearest_on_triangles(pts: np.ndarray, tri: np.ndarray):
    """Exact nearest point on the triangles for every point, in numpy without a Python loop per
    point (a deviation map asks for every face of the part): the distance to the triangles of
    the 8 nearest triangle centroids bounds it, and only triangles whose bounding box, grown by
    that bound, holds the point can be nearer."""
    from scipy.spatial import cKDTree

    from cutsim.reports.measure import _closest_on_triangles

    n, m = len(pts), len(tri)
    cen = tri.mean(axis=1)
    lo, hi = tri.min(axis=1), tri.max(axis=1)
    best = np.full(n, np.inf)
    near = np.zeros_like(pts)
    idx = np.zeros(n, dtype=np.int64)

    def test(pi, ti):
        """Distances of the pairs (point pi, triangle ti); keep the best per point."""
        for s in range(0, len(pi), 400_000):
            a, b = pi[s:s + 400_000], ti[s:s + 400_000]
            t = tri[b]
            qq = _closest_on_triangles(pts[a], t[:, 0], t[:, 1], t[:, 2], t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
            dd = np.linalg.norm(qq - pts[a], axis=1)
            order = np.lexsort((dd, a))  # per point the nearest first
            a, dd, qq, b = a[order], dd[order], qq[order], b[order]
            first = np.concatenate([[True], a[1:] != a[:-1]])
            a, dd, qq, b = a[first], dd[first], qq[first], b[first]
            better = dd < best[a]
            best[a[better]], near[a[better]], idx[a[better]] = dd[better], qq[better], b[better]

    kk = min(8, m)
    _, cnear = cKDTree(cen).query(pts, k=kk)
    test(np.repeat(np.arange(n), kk), np.asarray(cnear).reshape(n, kk).ravel())
    order = np.lexsort((pts[:, 1], np.floor(pts[:, 0] / max(1e-9, float(np.ptp(pts[:, 0])) / 64.0))))
    for i in range(0, n, 256):  # spatially compact groups of points: first the boxes near the group
        g = order[i:i + 256]
        p, r = pts[g], best[g] + 1e-9
        cols = np.flatnonzero(np.all((lo <= p.max(axis=0) + r.max()) & (hi >= p.min(axis=0) - r.max()), axis=1))
        if not len(cols):
            continue
        inside = np.all((p[:, None, :] >= lo[cols][None] - r[:, None, None])
                        & (p[:, None, :] <= hi[cols][None] + r[:, None, None]), axis=2)
        pi, ti = np.nonzero(inside)
        test(g[pi], cols[ti])
    return best, near, idx


def _deviation_cmap(k: float):
    """Diverging bands of one tolerance each from -k to +k tolerances (blue gouge, red excess),
    the two bands within +-tol one neutral pale green."""
    import matplotlib
    from matplotlib.colors import ListedColormap

    n = max(1, int(round(k)))
    rdbu = matplotlib.colormaps["RdBu_r"]
    t = [0.05 + 0.25 * i / max(1, n - 2) for i in range(n - 1)]  # from the dark end towards the middle
    blues = [rdbu(x) for x in t]
    reds = [rdbu(1.0 - x) for x in reversed(t)]
    return ListedColormap(blues + ["#dcefd5", "#dcefd5"] + reds), 2 * n


def deviation_view(result, design, spec=None, progress=None) -> View:
    """Each face of the part coloured by its signed distance to ``design`` (a manifold)."""
    v, f, d, cen = face_deviation(result.part, design, progress)
    p = _plotter()
    tol = None
    if spec is not None and spec.get("max_deviation") is not None:
        tol = float(spec["max_deviation"])
    if not tol:
        tol = 2.0 * float(result.report.get("tolerance") or result.setup.tolerance)
    lim = DEV_K * tol
    part = _polydata(v, f)
    part.cell_data["deviation mm"] = np.clip(d, -lim, lim)
    cmap, n = _deviation_cmap(DEV_K)
    p.add_mesh(part, scalars="deviation mm", cmap=cmap, n_colors=n, clim=(-lim, lim), smooth_shading=False,
               ambient=0.35, diffuse=0.7,
               reset_camera=False,
               scalar_bar_args={"color": "black", "fmt": "%.3f", "n_labels": n + 1,
                                "title": " ", "position_x": 0.45, "position_y": 0.83, "height": 0.07, "width": 0.52, "vertical": False,
                                "label_font_size": 12, "title_font_size": 13})
    notes = []
    pts, labels = [], []
    if len(d):
        kmin, kmax = int(np.argmin(d)), int(np.argmax(d))
        for kk, what in ((kmin, "worst gouge"), (kmax, "worst excess")):
            if (what == "worst gouge" and d[kk] < 0) or (what == "worst excess" and d[kk] > 0):
                c = cen[kk]
                s = (f"{what} {_num(float(d[kk]))} mm at X{_num(c[0], 2)} Y{_num(c[1], 2)} Z{_num(c[2], 2)}"
                     + ("  OUT OF TOL" if abs(d[kk]) > tol else ""))
                pts.append(c)
                labels.append(s)
                notes.append(s)
    if pts:
        p.add_point_labels(np.array(pts), labels, font_size=13, text_color="black", point_color="#ff00ff",
                           point_size=14, render_points_as_spheres=True, shape_color="white", shape_opacity=0.85,
                           always_visible=True, reset_camera=False, name="worst")
    within = float(np.mean(np.abs(d) <= tol)) if len(d) else 1.0
    p.add_text(f"{spec['name'] if spec else 'design'}: deviation from the design per face, mm; "
               f"{100 * within:.1f} % of the faces within \u00b1{tol:g} mm", position=(12, HEIGHT - 28),
               font_size=11, color="black")
    view = _iso(p, result, f"Deviation from the design per face (centroid to design surface): blue gouge, red "
                f"excess, pale green within the tolerance \u00b1{tol:g} mm; the scale stops at \u00b1{lim:g} mm.",
                name="deviation.png", notes=notes, zoom=0.85)
    view.ticks["deviation mm"] = [float(x) for x in np.linspace(-lim, lim, n + 1)]
    view.mesh = part
    part.cell_data["deviation (unclipped) mm"] = d
    return view


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
