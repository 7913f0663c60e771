"""Off-screen PNG views of a result (``cutsim simulate ... --images``). pyvista is imported inside
the functions only, so the rest of cutsim works without it.

Views (all WIDTH x HEIGHT pixels, white background, the same two-light setup, fixed cameras):
- ``iso.png``: isometric view of the part with the stock's feature edges as a thin outline and
  labelled axes with tick marks (the scale);
- lathe ``section.png``: the part cut by the XZ plane (y <= 0 kept, capped), seen along +Y in
  parallel projection with the stock outline of that section and a grid in mm;
- mill ``top.png``: the part from above in parallel projection, coloured by height z (scalar bar)
  with the stock outline;
- with a design check, ``deviation.png``: the part coloured by its signed distance to the design
  (blue = gouge, red = excess, symmetric range, scalar bar).
"""
from __future__ import annotations

import io

import numpy as np

WIDTH, HEIGHT = 1024, 768
FILES_LATHE = ("iso.png", "section.png")
FILES_MILL = ("iso.png", "top.png")


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


def _mesh(man):
    m = man.to_mesh()
    return _polydata(np.asarray(m.vert_properties, dtype=np.float64)[:, :3], np.asarray(m.tri_verts, dtype=np.int64))


def _plotter():
    pv = _pv()
    p = pv.Plotter(off_screen=True, window_size=(WIDTH, HEIGHT), lighting="light kit")
    p.set_background("white")
    return p


def _png(p) -> bytes:
    img = p.screenshot(None, return_img=True)
    p.close()
    from PIL import Image

    buf = io.BytesIO()
    Image.fromarray(np.asarray(img)).save(buf, format="PNG", optimize=False)
    return buf.getvalue()


def _stock_outline(result):
    edges = _mesh(result.stock).extract_feature_edges(feature_angle=30.0, boundary_edges=False,
                                                      non_manifold_edges=False, manifold_edges=False)
    return edges


def _axes(p, bounds):
    p.show_bounds(bounds=bounds, grid=False, location="outer", color="black", font_size=10, xtitle="X mm",
                  ytitle="Y mm", ztitle="Z mm", fmt="%.0f")


def _iso_png(p, result) -> bytes:
    """The plotter's PNG from the isometric view, with the stock's outline and axes."""
    p.add_mesh(_stock_outline(result), color="#555555", line_width=1.0, opacity=0.6)
    b = result.stock.bounding_box()
    _axes(p, (b[0], b[3], b[1], b[4], b[2], b[5]))
    p.view_isometric()
    p.reset_camera()
    return _png(p)


def iso_view(result) -> bytes:
    p = _plotter()
    part = _mesh(result.part)
    p.add_mesh(part, color="#b8c4cc", smooth_shading=False, specular=0.2)
    return _iso_png(p, result)


def section_view(result) -> bytes:
    """Lathe: the axial section at angle 0 (the XZ plane, y <= 0 kept), along +Y."""
    pv = _pv()
    p = _plotter()
    part = _mesh(result.part).clip_closed_surface(normal=(0.0, 1.0, 0.0), origin=(0.0, 0.0, 0.0))
    stock_sec = _mesh(result.stock).slice(normal=(0.0, 1.0, 0.0), origin=(0.0, 0.0, 0.0))
    if stock_sec.n_points:
        p.add_mesh(stock_sec, color="#d04020", line_width=1.5)
    b = result.stock.bounding_box()
    # frame: the first thread check's z range (one lead around it) on the +X side, else the +X half
    threads = [c for c in result.setup.checks if c["kind"] == "thread"]
    rmax = max(abs(v) for v in (b[0], b[1], b[3], b[4]))
    if threads:
        z0, z1 = threads[0]["z"][0] - threads[0]["lead"], threads[0]["z"][1] + threads[0]["lead"]
        z0, z1 = max(z0, b[2]), min(z1, b[5])
        x0 = max(0.0, rmax - max(3.0, 0.25 * (z1 - z0)))
    else:
        z0, z1, x0 = b[2], b[5], 0.0
    x1 = rmax + 0.05 * (rmax - x0)
    if x0 > 0:
        part = part.clip_closed_surface(normal=(1.0, 0.0, 0.0), origin=(x0, 0.0, 0.0))
    p.add_mesh(part, color="#b8c4cc", smooth_shading=False)
    p.add_ruler((x1, -1.0, z0), (x1, -1.0, z1), title="Z mm", label_color="black", tick_color="black",
                font_size_factor=0.6, label_format="%.1f", flip_range=False)
    p.add_ruler((x0, -1.0, z0), (x1, -1.0, z0), title="radius mm", label_color="black", tick_color="black",
                font_size_factor=0.6, label_format="%.1f")
    cx, cz = (x0 + x1) / 2 + 0.1 * (x1 - x0), (z0 + z1) / 2
    p.camera_position = [(cx, -1000.0, cz), (cx, 0.0, cz), (0.0, 0.0, 1.0)]
    p.enable_parallel_projection()
    p.camera.parallel_scale = 0.65 * max(z1 - z0, (x1 - x0) * HEIGHT / WIDTH)
    del pv
    return _png(p)


def top_view(result) -> bytes:
    """Mill: the part from above, coloured by height."""
    p = _plotter()
    part = _mesh(result.part)
    part["z mm"] = part.points[:, 2]
    p.add_mesh(part, scalars="z mm", cmap="viridis", smooth_shading=False,
               scalar_bar_args={"color": "black", "vertical": True, "fmt": "%.2f"})
    p.add_mesh(_stock_outline(result), color="#555555", line_width=1.0)
    b = result.stock.bounding_box()
    p.show_grid(bounds=(b[0], b[3], b[1], b[4], b[5], b[5]), color="black", font_size=10, xtitle="X mm",
                ytitle="Y mm", fmt="%.0f", location="outer")
    p.view_xy()
    p.enable_parallel_projection()
    p.reset_camera()
    return _png(p)


def deviation_view(result, design) -> bytes:
    """The part coloured by signed distance to ``design`` (a manifold): blue gouge, red excess."""
    from cutsim.stock.measure import signed_deviation

    p = _plotter()
    v, f, d = signed_deviation(result.part, design)
    part = _polydata(v, f)
    part["deviation mm"] = d
    lim = max(float(np.max(np.abs(d))) if len(d) else 0.0, 1e-3)
    p.add_mesh(part, scalars="deviation mm", cmap="coolwarm", clim=(-lim, lim), smooth_shading=False,
               scalar_bar_args={"color": "black", "vertical": True, "fmt": "%.3f"})
    return _iso_png(p, result)


def render_images(result) -> dict[str, bytes]:
    """PNG views of ``result``: {file name: bytes} (see the module docstring)."""
    from cutsim.stock.measure import load_solid

    out = {"iso.png": iso_view(result)}
    if result.setup.machine.kind == "lathe":
        out["section.png"] = section_view(result)
    else:
        out["top.png"] = top_view(result)
    designs = [c for c in result.setup.checks if c["kind"] == "design"]
    if designs:
        out["deviation.png"] = deviation_view(result, load_solid(designs[0]["path"]))
    return out
