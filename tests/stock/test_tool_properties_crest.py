"""The crest a full-profile thread insert cuts, over both hands, both feed directions, outside
and inside, several pitches, starts and root radii (docs/setup.md, "Lathe inserts": form = "full").

The insert (ISO 68-1 basic profile, H = sqrt(3)/2 P) points at the part with its tip; its
shoulders cut the crest at a fixed distance from the tip, read from the profile's definition:

- outside: the tip forms the bolt's root, a flat P/4 wide H/4 above the fundamental triangle's
  apex, or a nose of radius rr whose lowest point is rr above it; the crest is the major diameter,
  7H/8 above the apex: ``tip + 5H/8`` (flat) or ``tip + 7H/8 - rr``;
- inside: the tip forms the nut's root, a flat P/8 wide H/8 above the apex (or the nose rr); the
  crest is the minor diameter, 3H/4 above the apex: ``tip - 5H/8`` (flat) or ``tip - (3H/4 - rr)``
  in radius.

So a pass with its tip at X cuts the crest at radius X/2 +- that distance whatever the hand (M03
or M04), the direction it feeds (to -Z or +Z), the lead and the starts. The blank is 0.1 mm
(outside: larger, inside: smaller bore) beyond the crest, so a crest left uncut reads the blank.
The crest surface is the shoulders' edge swept along chords of the helix, on the axis side of it
(docs/setup.md): it lies within the tolerance of the true radius. Measured independently on the
part mesh (trimesh half-plane sections, each at the middle of the widest vertex-free gap within 1
degree of the angle asked for: never on a construction seam), in a slab clear of both ends.

The wrong part: the same thread with every pass 0.02 mm short of the depth (radially), whose
crest lies 0.02 mm off (ten times the tolerance): the same assertion must fail.
"""
from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import cutsim

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from support.geometry import load, section  # noqa: E402

TOL = 0.002
SHALLOW = 0.02  # mm, radial: the wrong part
BLANK = 0.1  # mm beyond the crest
SIM = settings(max_examples=14, deadline=None, derandomize=True, database=None,
               suppress_health_check=[HealthCheck.too_slow])


def crest_offset(side: str, pitch: float, rr: float) -> float:
    """Radial distance from the insert's tip to the crest it cuts (module docstring)."""
    big_h = math.sqrt(3.0) / 2.0 * pitch
    if side == "outside":
        return 7.0 * big_h / 8.0 - rr if rr else 5.0 * big_h / 8.0
    return 3.0 * big_h / 4.0 - rr if rr else 5.0 * big_h / 8.0


def clear_angles(mesh, phis, window: float = 1.0) -> list[float]:
    """Each angle moved to the middle of the widest gap between the mesh's vertex angles
    (modulo 180: a section is of the whole plane) within +-window degrees."""
    v = mesh.vertices
    v = v[np.hypot(v[:, 0], v[:, 1]) > 1e-6]
    a = np.sort(np.degrees(np.arctan2(v[:, 1], v[:, 0])) % 180.0)
    out = []
    for phi in phis:
        p0 = phi % 180.0
        near = a[(a > p0 - window) & (a < p0 + window)]
        edges = np.concatenate([[p0 - window], near, [p0 + window]])
        k = int(np.argmax(np.diff(edges)))
        out.append(phi + 0.5 * (edges[k] + edges[k + 1]) - p0)
    return out


def crest_radii(mesh, side: str, zlo: float, zhi: float, r_limit: float) -> np.ndarray:
    """Per section the crest radius in the slab zlo..zhi: outside the largest radius of the
    section, inside the smallest (the nut's wall nearer the axis than ``r_limit``)."""
    out = []
    for phi in clear_angles(mesh, [17.0, 95.0, 163.0, 241.0, 302.0]):
        s = section(mesh, phi).reshape(-1, 2)
        s = s[(s[:, 1] > zlo) & (s[:, 1] < zhi)]
        if side == "outside":
            out.append(s[:, 0].max())
        else:
            out.append(s[s[:, 0] < r_limit, 0].min())
    return np.array(out)


def run_thread(tmp_path, side, spindle, toward, pitch, starts, d, rr, short: float):
    """The thread cut with the insert's tip at the depth for major (outside) or minor (inside)
    diameter ``d`` at the crest, every pass ``short`` mm (radially) short of it."""
    length = 12.0
    off = crest_offset(side, pitch, rr)
    if side == "outside":
        r_tip = d / 2.0 - off + short
        stock = f'shape = "cylinder"\ndiameter = {d + 2 * BLANK:.6f}\nz = [{-length}, 0.0]'
        clear = d + 2 * BLANK + 3.0
    else:
        r_tip = d / 2.0 + off - short
        rin, rout = d / 2.0 - BLANK, d / 2.0 + 2.0 * pitch + 3.0
        stock = f'shape = "revolve"\nprofile = [[{rin:.6f}, 0], [{rout:.6f}, 0], [{rout:.6f}, {-length}], [{rin:.6f}, {-length}]]'
        clear = 2.0 * rin - 1.0
    tool = (f'kind = "thread"\nform = "full"\npitch = {pitch}\ntip_radius = {rr:.6f}\nside = "{side}"\n'
            f'height = {2.0 * pitch:.4f}')
    setup = tmp_path / "crest.toml"
    setup.write_text(f'[machine]\nkind = "lathe"\ndialect = "cnc8x6"\n\n[stock]\n{stock}\n\n[[tool]]\nnumber = 1\n{tool}\n')
    z0, z1 = (3.0, -length - 2.0) if toward == "-Z" else (-length - 3.0, 2.0)
    lead = pitch * starts
    lines = [f"G00 X{clear:.4f} Z{z0}", f"{spindle} S500"]
    for k in range(starts):
        lines += [f"X{2 * r_tip:.6f}", f"G33 Z{z1} I{k * 360.0 / starts:.4f} F{lead:.5f}", f"G00 X{clear:.4f}", f"Z{z0}"]
    res = cutsim.simulate("crest.nc", str(setup), text="\n".join(lines) + "\nM30\n", tolerance=TOL)
    return load(res)


@SIM
@given(side=st.sampled_from(["outside", "inside"]), spindle=st.sampled_from(["M03", "M04"]),
       toward=st.sampled_from(["-Z", "+Z"]), pitch=st.sampled_from([0.75, 1.0, 1.5, 2.0]),
       starts=st.integers(1, 3), d_frac=st.floats(0.0, 1.0), root=st.sampled_from([0.0, 0.125, 0.2]))
def test_full_profile_insert_cuts_the_crest(tmp_path_factory, side, spindle, toward, pitch, starts, d_frac, root):
    tmp_path = tmp_path_factory.mktemp("crest")
    d = round(max(10.0, 8.0 * pitch) + d_frac * 30.0, 3)
    rr = root * pitch
    verdicts = []
    for short in (0.0, SHALLOW):
        mesh = run_thread(tmp_path, side, spindle, toward, pitch, starts, d, rr, short)
        radii = crest_radii(mesh, side, -9.0, -3.0, d / 2.0 + pitch)
        err = radii - d / 2.0
        ok = bool(np.all(np.abs(err) <= TOL + 1e-6))
        verdicts.append((ok, np.round(err, 5).tolist()))
    assert verdicts[0][0], (side, spindle, toward, pitch, starts, d, rr, verdicts[0])
    assert not verdicts[1][0], ("the shallow part passed", side, spindle, toward, pitch, starts, d, rr, verdicts[1])
