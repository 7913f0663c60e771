"""The plumbing of the PNG views (reports/images.py, reports/views3d.py): off-screen pyvista
plotters, the view record, round ticks, the 2D chart with rulers in workpiece coordinates and the
colours shared by the views. pyvista is imported inside the functions only, so the rest of cutsim
works without it."""
from __future__ import annotations

import io
import math
from dataclasses import dataclass, field

import numpy as np

from cutsim.stock.arrays import solid_arrays

WIDTH, HEIGHT = 1024, 768
MAX_FLOORS = 12  # more flat levels than this: continuous colours with contour lines
MIN_FLOOR_AREA = 0.01  # mm^2 (0.1 x 0.1 mm): a flat level smaller than this in all is no floor
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
    from vtkmodules.vtkRenderingCore import vtkMapper

    vtkMapper.SetResolveCoincidentTopologyToPolygonOffset()  # edges drawn on a face stay in front of it
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


def _mesh(man):
    return _polydata(*solid_arrays(man))


def _plotter(lighting="light kit", size: tuple[int, int] = (WIDTH, HEIGHT)):
    pv = _pv()
    p = pv.Plotter(off_screen=True, window_size=size, lighting=lighting)
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


def world_text(p, pos, s, size=14, color="black", halign="center", valign="center", bold=False, name=None):
    """A text actor of plotter ``p`` anchored at the world point ``pos``, justified about it; bold
    text (annotations) on a white box so it stays readable over the drawing."""
    from vtkmodules.vtkRenderingCore import vtkTextActor

    a = vtkTextActor()
    a.SetInput(s)
    tp = a.GetTextProperty()
    tp.SetFontSize(size)
    tp.SetColor(*_rgb(color))
    tp.SetFontFamilyToArial()
    tp.SetBold(bold)
    if bold:
        tp.SetBackgroundColor(1.0, 1.0, 1.0)
        tp.SetBackgroundOpacity(0.85)
    {"left": tp.SetJustificationToLeft, "center": tp.SetJustificationToCentered,
     "right": tp.SetJustificationToRight}[halign]()
    {"top": tp.SetVerticalJustificationToTop, "center": tp.SetVerticalJustificationToCentered,
     "bottom": tp.SetVerticalJustificationToBottom}[valign]()
    c = a.GetPositionCoordinate()
    c.SetCoordinateSystemToWorld()
    c.SetValue(*(float(v) for v in pos))
    p.add_actor(a, reset_camera=False, name=name)
    return a


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
        self.W, self.H = W, H = tuple(int(n) for n in p.window_size)
        u0, u1, v0, v1 = box
        ml, mr, mb, mt = margins
        aw, ah = W - ml - mr, H - mb - mt
        s = min(aw / max(u1 - u0, 1e-9), ah / max(v1 - v0, 1e-9))
        du, dv = (aw / s - (u1 - u0)) / 2, (ah / s - (v1 - v0)) / 2
        if not widen_v:  # a long slender part: the frame hugs it, the page stays white around it
            dv = 0.0
        if anchor_v0:  # keep v0 (the axis of a lathe section) at the bottom: widen upwards only
            v0, v1 = v0 + dv, v1 + dv
        self.box = (u0 - du, u1 + du, v0 - dv, v1 + dv)
        self.s = s
        uc = (u0 + u1) / 2 - (ml + aw / 2 - W / 2) / s
        vc = (self.box[2] + self.box[3]) / 2 - (mb + ah / 2 - H / 2) / s
        p.camera_position = [(uc, vc, plane_z + 1000.0), (uc, vc, plane_z), (0.0, 1.0, 0.0)]
        p.enable_parallel_projection()
        p.camera.parallel_scale = H / (2 * s)
        self.ticks = {}
        self.n_text = 0
        self.pix = (uc, vc)

    def pixel(self, u: float, v: float) -> tuple[int, int]:
        """(row, column) in the PNG of the world point (u, v)."""
        col = self.W / 2 + (u - self.pix[0]) * self.s
        row = self.H / 2 - (v - self.pix[1]) * self.s
        return int(round(row)), int(round(col))

    def world(self, x_px: float, y_px: float) -> tuple[float, float]:
        """World (u, v) of the pixel (x_px, y_px) counted from the bottom left."""
        return self.pix[0] + (x_px - self.W / 2) / self.s, self.pix[1] + (y_px - self.H / 2) / self.s

    def px(self, n: float) -> float:
        """``n`` pixels in mm."""
        return n / self.s

    def pt(self, u, v, dz: float = 0.0):
        return (float(u), float(v), self.z + dz)

    def text(self, u, v, s, size=14, color="black", halign="center", valign="center", bold=False, dz=2.0):
        self.n_text += 1
        return world_text(self.p, self.pt(u, v, dz), s, size, color, halign, valign, bold, name=f"text-{self.n_text}")

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

    def axes(self, utitle, vtitle, v2=None, v2title=None, n=8, grid=True, limits=None):
        """Frame, ticks and labels. ``v2``: a function mapping v to a second scale on the right.
        ``limits`` (u0, u1, v0, v1): the ticks stay within it (a top view's rulers span the stock)."""
        u0, u1, v0, v1 = self.box
        a0, a1, b0, b1 = limits if limits is not None else self.box
        a0, a1, b0, b1 = max(u0, a0), min(u1, a1), max(v0, b0), min(v1, b1)
        big = max(u1 - u0, v1 - v0)
        nu = max(3, int(round(n * (a1 - a0) / big)))
        nv = max(3, int(round(n * (b1 - b0) / big)))
        tu, tv = nice_ticks(a0, a1, nu), nice_ticks(b0, b1, nv)
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
        self.p.add_text(s, position=(12, self.H - 28), font_size=11, color="black")

    def legend(self, items, y_px: float | None = None):
        """Colour swatches with labels along the top right: [(label, color)]."""
        y_px = self.H - 44 if y_px is None else y_px
        widths = [7.0 * len(label) + 22 for label, _ in items]
        x = self.W - 14 - sum(widths) - 16 * max(0, len(items) - 1)
        for (label, color), w in zip(items, widths):
            a, b = self.world(x, y_px - 7)
            c, d = self.world(x + 14, y_px + 7)
            self.fill([np.array([(a, b), (c, b), (c, d), (a, d)])], color, dz=3.0)
            self.lines([((a, b), (c, b), (c, d), (a, d), (a, b))], color="#444444", dz=3.1)
            self.text(*self.world(x + 20, y_px), label, size=13, halign="left")
            x += w + 16


# ------------------------------------------------------------------------------------------------
# mill
# ------------------------------------------------------------------------------------------------
def floor_levels(v: np.ndarray, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per face: whether it faces up (a floor or the top) and the distinct Z of the floors (to
    0.001 mm, from the highest down). A level of less than MIN_FLOOR_AREA in all is a sliver left
    between passes, not a floor: its faces take the colour of the next floor below."""
    t = v[f]
    n = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
    ln = np.linalg.norm(n, axis=1)
    up = (ln > 0) & (n[:, 2] > 0.999 * np.where(ln > 0, ln, 1.0))
    zc = np.round(t[:, :, 2].mean(axis=1), 3)
    levels, inv = np.unique(zc[up], return_inverse=True)
    area = np.bincount(inv.ravel(), weights=0.5 * ln[up], minlength=len(levels))
    return up, levels[area >= MIN_FLOOR_AREA][::-1]


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


def _stock_outline(result):
    return _mesh(result.stock).extract_feature_edges(feature_angle=30.0, boundary_edges=False,
                                                     non_manifold_edges=False, manifold_edges=False)
