"""Axial tools on a lathe's spindle axis, given as solids of revolution: the centre drill and the
ISO metric tap (docs/setup.md, ``[[tool]]``).

Every shape is a half-section in the tool's frame: u the radius from the tool's axis, v along it
(+Z), the control point (what X and Z program) at the tip on the axis.

- A centre drill: the pilot's point cone (``point_angle``), the pilot cylinder (``diameter``) up
  to ``pilot_length`` from the tip, the countersink cone of the included ``countersink`` angle up
  to the body's diameter (``body_diameter``), the body up to ``length``.
- A tap: the ISO 68-1 basic profile of the nut's groove as its teeth (crest flat P/8 at the major
  radius D/2, 60 degree flanks), continued down to its root flat P/8 at D/2 - 3H/4 (H/8 below the
  nut's minor radius D1/2: the root never touches a bore of D1); a crest is centred on the tip
  height and every pitch above it; the chamfer is the cone from the root radius at the tip to D/2
  at ``chamfer``; the tap ends at ``length`` (its thread length).

With the spindle turning an axial tool sweeps its envelope revolved (``section``: both sides of
the axis, as a drill). Under screw motion (G33 along Z on the axis) a tap is its core (a solid of
revolution: moved along the axis it sweeps the revolved region ``core_region``) and its teeth
(``tap_teeth``: the band from just inside the root outwards, swept by the screw motion), which
together sweep the tap exactly. With the spindle stopped it is its envelope (``body``: convex
frustums, exact for a centre drill; a tap's envelope is the cylinder over its teeth).
"""
from __future__ import annotations

import math

import manifold3d as m3d
import numpy as np

from cutsim.base.specs import ToolSpec
from cutsim.kinematics.paths import segment_angle

COUNTERSINKS = (60.0, 90.0)  # degrees: the centre drills' countersink angles (DIN 333 A, ISO 866 / 90)
H_FACTOR = math.sqrt(3.0) / 2.0  # ISO 68-1: the fundamental triangle's height H = H_FACTOR x P
CORE_OVERLAP = 0.125  # x H: the tap's teeth band reaches this far inside its root (overlaps the core)


def tap_root(tool: ToolSpec) -> float:
    """A tap's root radius: D/2 - 3H/4."""
    return tool.diameter / 2.0 - 0.75 * H_FACTOR * tool.pitch


def countersink_top(tool: ToolSpec) -> float:
    """Height above the tip where a centre drill's countersink reaches the body's diameter."""
    half = math.radians(tool.countersink) / 2.0
    return tool.pilot_length + (tool.body_diameter - tool.diameter) / 2.0 / math.tan(half)


def outline(tool: ToolSpec) -> np.ndarray:
    """The envelope's outline (u, v) from the tip (u may be 0 there) up to ``length``: u never
    decreases with v (each piece between two rows is a frustum)."""
    if tool.kind == "centredrill":
        r, half = tool.diameter / 2.0, math.radians(tool.point_angle) / 2.0
        hp = r / math.tan(half) if tool.point_angle < 180.0 else 0.0
        pts = [(0.0, 0.0), (r, hp), (r, tool.pilot_length), (tool.body_diameter / 2.0, countersink_top(tool)),
               (tool.body_diameter / 2.0, tool.length)]
    else:
        pts = [(0.0, 0.0), (tap_root(tool), 0.0), (tool.diameter / 2.0, tool.chamfer),
               (tool.diameter / 2.0, tool.length)]
    out = [pts[0]]
    for p in pts[1:]:
        if abs(p[0] - out[-1][0]) > 1e-12 or abs(p[1] - out[-1][1]) > 1e-12:
            out.append(p)
    return np.array(out, dtype=float)


def section(tool: ToolSpec) -> np.ndarray:
    """The whole axial section (both sides of the axis), whose revolved sweep with the spindle
    turning is what the tool cuts (the revolve keeps r >= 0)."""
    half = outline(tool)
    right = half[half[:, 0] > 0]
    left = right[::-1] * [-1.0, 1.0]
    start = [half[0]] if half[0, 0] == 0 else []
    return np.vstack(start + [right, left])


def frustum_volume(h: float, r1: float, r2: float) -> float:
    return math.pi * h * (r1 * r1 + r1 * r2 + r2 * r2) / 3.0


def body(tool: ToolSpec, tol: float) -> list[np.ndarray]:
    """3D convex pieces (vertex clouds) of the envelope, one frustum per row pair of ``outline``
    (the spindle stopped: the tool as a rigid body)."""
    half = outline(tool)
    r_max = float(half[:, 0].max())
    n = max(8, math.ceil(2.0 * math.pi / segment_angle(r_max, tol)))
    a = np.linspace(0.0, 2.0 * math.pi, n, endpoint=False)
    ring = np.column_stack([np.cos(a), np.sin(a)])
    out = []
    for (u0, v0), (u1, v1) in zip(half[:-1], half[1:]):
        if v1 - v0 <= 0:
            continue
        layers = [np.column_stack([ring * max(u, 1e-9), np.full(n, v)]) for u, v in ((u0, v0), (u1, v1))]
        out.append(np.vstack(layers))
    return out


def tap_teeth(tool: ToolSpec) -> np.ndarray:
    """The tap's teeth in one half-plane (u from just inside the root radius, CORE_OVERLAP x H,
    out to D/2; v from the tip to ``length``), cut by the chamfer cone: the profile the screw
    motion sweeps. Crests (flat P/8 at D/2) centred at v = k P, roots (flat P/8) at k P + P/2."""
    p, big = tool.pitch, tool.diameter / 2.0
    root = tap_root(tool)
    r_in = root - CORE_OVERLAP * H_FACTOR * p
    zig = []
    for k in range(-1, math.ceil(tool.length / p) + 2):
        c = k * p
        zig += [(big, c - p / 16.0), (big, c + p / 16.0), (root, c + p / 2.0 - p / 16.0), (root, c + p / 2.0 + p / 16.0)]
    zig = np.array(zig)
    teeth = np.vstack([[(r_in, zig[0, 1])], zig, [(r_in, zig[-1, 1])]])
    env = np.vstack([[(r_in, 0.0)], outline(tool)[1:], [(r_in, tool.length)]])
    cs = m3d.CrossSection([teeth], m3d.FillRule.Positive) ^ m3d.CrossSection([env], m3d.FillRule.Positive)
    polys = cs.to_polygons()
    if len(polys) != 1:
        raise ValueError("a tap's teeth band is one region")
    return np.asarray(polys[0], dtype=float)


def core_region(tool: ToolSpec, z0: float, z1: float) -> m3d.CrossSection:
    """The tap's core (the cylinder of its root radius from the tip to ``length``) moved along the
    axis with its tip from z0 to z1: the axial section of what it sweeps (a solid of revolution
    moved along its own axis sweeps the revolved hull of its two end sections)."""
    r = tap_root(tool)
    lo, hi = min(z0, z1), max(z0, z1) + tool.length
    return m3d.CrossSection([np.array([[-r, lo], [r, lo], [r, hi], [-r, hi]])])
