"""The 3D views: ``iso.png`` and ``deviation.png``, drawn in parallel projection under one camera
convention shared with the flat views (top view, sections), so a feature sits on the same side in
every image:

- mill: X to the right and Y away from the viewer in every view. The top view looks down -Z (X
  right, Y up); iso and deviation look from the front left above, as a machinist standing at the
  front of the machine (on the -Y side, a little to the left) sees the part: the camera lies in
  direction MILL_VIEW = (-1, -2, 1.5) from the part's centre, Z up;
- lathe: Z across to the right (the chuck on the left), X up, in every view. Sections show the
  half-plane through +X that way; iso and deviation look from the operator's side (+Y, which points
  at the viewer when X is up and Z to the right), a little from above (+X) and from the face end
  (+Z): LATHE_VIEW = (0.45, 1, 0.35), X up.

The axes are three edges of the stock's bounding box running exactly from the stock's minimum to
its maximum, with round ticks inside that range, as many as fit without their labels touching
(world-anchored text actors, read back by :func:`cutsim.reports.plot.text_actors`).
"""
from __future__ import annotations

import math

import numpy as np

from cutsim.stock.arrays import solid_arrays

from .plot import (DEV_K, HEIGHT, MAX_FLOORS, PART_COLOR, WALL_COLOR, View, _face_floor_index,
                   _floor_colors, _fmt_tick, _num, _plotter, _polydata, _pv, _rgb, _stock_outline, floor_levels,
                   nice_ticks, world_text)

MILL_VIEW = (-1.0, -2.0, 1.5)  # from the part towards the camera; Z up
LATHE_VIEW = (0.45, 1.0, 0.35)  # from the part towards the camera; X up
WITHIN_COLOR = "#dcefd5"  # deviation within the tolerance
EDGE_COLOR = "#1e2226"  # the part's feature edges (rims, floors' outlines)
FEATURE_ANGLE = 30.0  # degrees between neighbouring faces' normals that make an edge a feature edge


def _unit(v) -> np.ndarray:
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v)


class Camera3D:
    """A parallel projection of the box ``bounds`` (xmin, xmax, ymin, ymax, zmin, zmax) seen from
    ``direction`` (from the box towards the camera) with ``up`` pointing up, fitted into the window
    inside pixel ``margins`` (left, right, bottom, top). ``pixel`` maps world points to PNG pixels."""

    def __init__(self, p, bounds, direction, up, margins=(110, 90, 90, 70)):
        self.p = p
        self.W, self.H = W, H = tuple(int(n) for n in p.window_size)
        self.bounds = tuple(float(b) for b in bounds)
        x0, x1, y0, y1, z0, z1 = self.bounds
        d = _unit(direction)
        view = -d
        self.right = _unit(np.cross(view, up))
        self.up = _unit(np.cross(self.right, view))
        corners = np.array([(x, y, z) for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)])
        u, v = corners @ self.right, corners @ self.up
        ml, mr, mb, mt = margins
        aw, ah = W - ml - mr, H - mb - mt
        s = min(aw / max(np.ptp(u), 1e-9), ah / max(np.ptp(v), 1e-9))
        uc = (u.min() + u.max()) / 2 - (ml + aw / 2 - W / 2) / s
        vc = (v.min() + v.max()) / 2 - (mb + ah / 2 - H / 2) / s
        centre = corners.mean(axis=0)
        focal = uc * self.right + vc * self.up + float(centre @ view) * view
        dist = 10.0 * float(np.linalg.norm(corners.max(axis=0) - corners.min(axis=0))) + 100.0
        p.camera_position = [tuple(focal - dist * view), tuple(focal), tuple(self.up)]
        p.enable_parallel_projection()
        p.camera.parallel_scale = H / (2 * s)
        self.s, self.uc, self.vc = float(s), float(uc), float(vc)
        self.centre = centre

    def screen(self, pt) -> np.ndarray:
        """Pixels (x to the right, y up) of the world point ``pt`` from the window's centre."""
        q = np.asarray(pt, dtype=float)
        return np.array([(q @ self.right - self.uc) * self.s, (q @ self.up - self.vc) * self.s])

    def pixel(self, x: float, y: float, z: float) -> tuple[int, int]:
        """(row, column) in the PNG of the world point (x, y, z)."""
        sx, sy = self.screen((x, y, z))
        return int(round(self.H / 2 - sy)), int(round(self.W / 2 + sx))


def _align(n) -> tuple[str, str]:
    """Text justification for a label placed in screen direction ``n`` from its anchor."""
    h = "right" if n[0] < -0.38 else "left" if n[0] > 0.38 else "center"
    v = "top" if n[1] < -0.38 else "bottom" if n[1] > 0.38 else "center"
    return h, v


def _fit_ticks(lo, hi, px_per_mm, along, size=12) -> list[float]:
    """Round ticks in [lo, hi], the most (up to 8 intervals) whose labels do not touch: a label
    w x h pixels takes w |along_x| + h |along_y| along an axis of screen direction ``along``."""
    for n in range(8, 0, -1):
        ticks = nice_ticks(lo, hi, n)
        if len(ticks) < 2:
            continue
        step = ticks[1] - ticks[0]
        w = max(0.62 * size * len(_fmt_tick(t, step)) + 6 for t in ticks)
        need = w * abs(along[0]) + (size + 6) * abs(along[1]) + 10
        if step * px_per_mm >= need:
            return ticks
    return []


def _axis3d(p, cam, k: int, fixed: dict, title: str) -> list[float]:
    """Axis ``k`` (0 X, 1 Y, 2 Z) along the stock box's edge at the ``fixed`` other coordinates
    ({axis: value}), from the stock's minimum to its maximum: line, ticks, labels and title placed
    on the side of the edge away from the box's centre. Returns the tick values."""
    pv = _pv()
    b = cam.bounds
    lo, hi = b[2 * k], b[2 * k + 1]
    e = np.eye(3)[k]
    base = np.zeros(3)
    for j, val in fixed.items():
        base[j] = val
    a_pt, b_pt = base + lo * e, base + hi * e
    along = cam.screen(b_pt) - cam.screen(a_pt)
    length = float(np.linalg.norm(along))
    along = along / length if length > 0 else np.array([1.0, 0.0])
    n = np.array([-along[1], along[0]])
    mid = (a_pt + b_pt) / 2
    if n @ (cam.screen(cam.centre) - cam.screen(mid)) > 0:
        n = -n
    # the world direction (in the plane of the two other axes) that the screen shows as n: labels
    # then sit at their tick's own coordinate along the axis
    others = [np.eye(3)[j] for j in range(3) if j != k]
    m = np.column_stack([cam.screen(o) - cam.screen(np.zeros(3)) for o in others])
    coef = np.linalg.lstsq(m, n, rcond=None)[0]
    w = coef[0] * others[0] + coef[1] * others[1]  # |screen(w)| = 1 pixel
    ticks = _fit_ticks(lo, hi, length / max(hi - lo, 1e-12), along)
    pts = [a_pt, b_pt]
    for t in ticks:
        q = base + t * e
        pts += [q, q + 6.0 * w]
    lines = np.hstack([np.full((len(pts) // 2, 1), 2), np.arange(len(pts)).reshape(-1, 2)]).ravel()
    p.add_mesh(pv.PolyData(np.array(pts, dtype=float), lines=lines), color="black", line_width=1.2,
               lighting=False, reset_camera=False, name=f"axis-{title}")
    h, v = _align(n)
    step = ticks[1] - ticks[0] if len(ticks) > 1 else 1.0
    for t in ticks:
        world_text(p, base + t * e + 10.0 * w, _fmt_tick(t, step), size=12, halign=h, valign=v)
    world_text(p, mid + (40.0 if abs(n[1]) > 0.5 else 50.0) * w, title, size=13, halign=h, valign=v, bold=True)
    return [float(t) for t in ticks]


def _axes(p, cam, lathe: bool) -> dict:
    """The three axes on the stock box edges nearest the viewer's outline (see the module doc)."""
    x0, x1, y0, y1, z0, z1 = cam.bounds
    if lathe:  # Z along the bottom front, X up at the chuck end, Y at the face end's bottom
        edges = [(2, {0: x0, 1: y1}, "Z mm"), (0, {1: y1, 2: z0}, "X mm"), (1, {0: x0, 2: z1}, "Y mm")]
    else:  # X along the front bottom, Y along the left bottom, Z up the front right corner
        edges = [(0, {1: y0, 2: z0}, "X mm"), (1, {0: x0, 2: z0}, "Y mm"), (2, {0: x1, 1: y0}, "Z mm")]
    return {title: _axis3d(p, cam, k, fixed, title) for k, fixed, title in edges}


def _feature_edges(mesh):
    return mesh.extract_feature_edges(feature_angle=FEATURE_ANGLE, boundary_edges=False, non_manifold_edges=False,
                                      manifold_edges=False)


def _iso(p, result, part, caption, name="iso.png", notes=None, margins=(110, 90, 90, 70)) -> View:
    """Stock outline, the part's feature edges, camera (module doc) and axes for a 3D view."""
    lathe = result.setup.machine.kind == "lathe"
    p.add_mesh(_stock_outline(result), color="#777777", line_width=1.0, opacity=0.6, reset_camera=False)
    p.add_mesh(_feature_edges(part), color=EDGE_COLOR, line_width=2.0, lighting=False, reset_camera=False,
               name="feature-edges")
    b = result.stock.bounding_box()
    bounds = (b[0], b[3], b[1], b[4], b[2], b[5])
    if lathe:
        cam = Camera3D(p, bounds, LATHE_VIEW, (1.0, 0.0, 0.0), margins)
    else:
        cam = Camera3D(p, bounds, MILL_VIEW, (0.0, 0.0, 1.0), margins)
    ticks = _axes(p, cam, lathe)
    return View(name, caption, p, ticks, notes or [], pixel=cam.pixel)


def iso_view(result) -> View:
    """The part in 3D (module doc for the camera); on a mill part the floors take their top-view
    colours, walls grey; the part's feature edges drawn."""
    p = _plotter()
    v, f = solid_arrays(result.part)
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
        cap = ("Isometric view from the front left (X to the right, Y away, Z up): floors in their top-view "
               "colours, walls grey, edges dark; the stock's outline in grey.")
    else:
        p.add_mesh(part, color=PART_COLOR, smooth_shading=False, specular=0.3, ambient=0.3, reset_camera=False)
        cap = ("Isometric view of the part as it sits in the lathe (Z to the right, X up, seen from the operator's "
               "side) with the stock's outline.")
    where = ("as it sits in the lathe: Z to the right, X up, from the operator's side"
             if result.setup.machine.kind == "lathe" else "from the front left above: X to the right, Y away, Z up")
    p.add_text(f"{result.report.get('program', '')}: view {where}", position=(12, HEIGHT - 28), font_size=11,
               color="black")
    view = _iso(p, result, part, cap)
    view.mesh = part
    return view


# ------------------------------------------------------------------------------------------------
# deviation
# ------------------------------------------------------------------------------------------------
def face_deviation(part, design, progress=None, chunk: int = 2000
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Part mesh (vertices, faces), per face the signed distance from its centroid to the design
    surface (positive outside the design: excess; negative inside: gouge) and the centroids.
    Computed in chunks of ``chunk`` faces with ``progress("deviation", i, n)`` (faces done)."""
    from cutsim.reports.measure import _point_triangle_distance

    pv_, pf = solid_arrays(part)
    dv, df = solid_arrays(design)
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
    return ListedColormap(blues + [WITHIN_COLOR, WITHIN_COLOR] + reds), 2 * n


def deviation_view(result, design, spec=None, progress=None) -> View:
    """Each face of the part coloured by its signed distance to ``design`` (a manifold), lit and
    with the part's feature edges so the shape reads where the part is within tolerance."""
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
    nd = max(0, -math.floor(math.log10(tol) + 1e-9)) + 1
    p.add_mesh(part, scalars="deviation mm", cmap=cmap, n_colors=n, clim=(-lim, lim), smooth_shading=False,
               ambient=0.3, diffuse=0.75, specular=0.1, reset_camera=False,
               scalar_bar_args={"color": "black", "fmt": f"%.{nd}f", "n_labels": n + 1, "title": " ",
                                "position_x": 0.45, "position_y": 0.83, "height": 0.07, "width": 0.52,
                                "vertical": False, "label_font_size": 12, "title_font_size": 13})
    notes = []
    pts, labels = [], []
    if len(d):
        kmin, kmax = int(np.argmin(d)), int(np.argmax(d))
        for kk, what in ((kmin, "worst gouge"), (kmax, "worst excess")):
            if (what == "worst gouge" and d[kk] < 0) or (what == "worst excess" and d[kk] > 0):
                c = cen[kk]
                s = (f"{what} {_num(float(d[kk]), nd)} mm at X{_num(c[0], 2)} Y{_num(c[1], 2)} Z{_num(c[2], 2)}"
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
    view = _iso(p, result, part, f"Deviation from the design per face (centroid to design surface), seen as "
                f"iso.png: blue gouge, red excess, pale green within the tolerance \u00b1{tol:g} mm; the scale "
                f"stops at \u00b1{lim:g} mm; the part's edges dark.", name="deviation.png", notes=notes,
                margins=(110, 90, 90, 190))
    view.ticks["deviation mm"] = [float(x) for x in np.linspace(-lim, lim, n + 1)]
    view.mesh = part
    part.cell_data["deviation (unclipped) mm"] = d
    return view
