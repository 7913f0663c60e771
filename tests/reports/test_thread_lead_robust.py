"""The lead and hand of ``measure_thread`` over a range that runs into incomplete thread: a lead-in or
runout ramp of a G33 thread (CNC8x6 ``E`` and ``J``), a tap's chamfer. Every number is derived from
the program: the lead is F (G33) or PIT (CYCLE840), the hand is M03 (right) or M04 (left) feeding
towards -Z, starts = the number of start angles I. A part cut with the lead 5 % long must measure
5 % long (and so fail a check of the programmed lead).

Before the lead was read from all the roots at once (``lead_fit``) one groove was followed once
round from the middle of the range: over Z-12..-4 of a left-hand M10x1.5 tapped under M4 it ran
into roots the tap's chamfer had cut shallow or shifted and read 1.44 for 1.5.
"""
from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

import cutsim
from cutsim.reports.measure import lead_fit, measure_thread

LEAD_TOL = 0.01  # mm per turn
TOLERANCE = 0.01  # simulation chordal tolerance
RAMP = 30.0  # degrees: machine constant 8 = (-)130000, the ramps' angle on X


# ---------------------------------------------------------------------------------------------
# the reported case: CYCLE840 left-hand M10x1.5 under M4, measured over Z-12 .. -4
def test_cycle840_left_hand_over_the_chamfer(tmp_path):
    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "interp" / "sinumerik"))
    import test_lathe_tapping as tapping

    res = tapping.run(tmp_path, "G95 S200 M4 F0.2", "CYCLE840(10, 0, 2, -15, , 0, 3, 5, 0, 10)")
    got = measure_thread(res.part, -12.0, -4.0, inside=True)
    # the range holds roots the chamfer (3 x 1.5 from the tip at Z-15) cut shallow (r < 4.8)
    assert min(r for _, _, r in got["roots"]) < 4.8
    assert got["lead"] == pytest.approx(1.5, abs=0.005) and got["hand"] == "left" and got["starts"] == 1


# ---------------------------------------------------------------------------------------------
# lead_fit on roots placed by the closed form z = z0 + s * lead * phi / 360 + k * pitch (+ the start's
# own shift), a third of the grooves displaced along their whole length or in single roots
@pytest.mark.parametrize("seed", range(6))
def test_lead_fit_ignores_a_minority_of_displaced_roots(seed):
    rng = np.random.default_rng(seed)
    starts, pitch = 1 + seed % 3, float(rng.uniform(0.5, 3.0))
    lead, s = starts * pitch, (1.0, -1.0)[seed % 2]
    phis = np.arange(36) * 10.0 + rng.uniform(-1.0, 1.0, 36)
    shift = rng.uniform(-0.1, 0.1, starts) * pitch  # every start a little off its nominal phase
    z0 = float(rng.uniform(-5.0, 5.0))
    grooves = range(6)
    per = []
    for j, phi in enumerate(phis):
        z = np.array([z0 + s * lead * phi / 360.0 + k * pitch + shift[k % starts] for k in grooves])
        z[0] += 0.25 * pitch  # a groove the chamfer cut shallow, its root off the helix
        z[1] += 0.03 * pitch  # ... and the lopsided one above it
        if j % 2 and rng.random() < 0.6:  # stray roots (never two in a row)
            z[int(rng.integers(2, 6))] += float(rng.uniform(0.03, 0.3)) * pitch * rng.choice([-1.0, 1.0])
        per.append(np.stack([z, np.full(len(z), 5.0)], axis=1))
    slope, links, degrees = lead_fit(per, phis, pitch)
    assert abs(slope) * 360.0 == pytest.approx(lead, abs=1e-9) and np.sign(slope) == s
    assert degrees == pytest.approx(360.0)


# ---------------------------------------------------------------------------------------------
# G33 threads with a lead-in and a runout (CNC8x6), inside and outside, 1-3 starts, either hand
def g33_case(seed: int) -> dict:
    rng = np.random.default_rng(seed)
    inside, starts = bool(seed % 2), 1 + seed % 3  # seeds 0-5: each side with 1, 2, 3 starts, both hands
    pitch = round(float(rng.uniform(0.5, 3.0)), 3)
    depth = 0.6134 * pitch  # ISO external thread depth, on the radius
    e, j = round(float(rng.uniform(3.0, 6.0)), 2), round(float(rng.uniform(3.0, 6.0)), 2)
    ramp = math.tan(math.radians(RAMP))
    bore, bar = 16.0, 30.0
    root = bore + 2.0 * depth if inside else bar - 2.0 * depth  # diameter
    start = root - 2.0 * e * ramp if inside else root + 2.0 * e * ramp  # the lead-in starts here
    # the range reaches into the lead-in, the runout or both (the ramps: Z2 .. 2-E, Z-22+J .. -22)
    ends = ("in", "out", "both")[int(rng.integers(0, 3))]
    full_hi, full_lo = 2.0 - e - 0.5, -22.0 + j + 0.5
    zhi = min(-0.2, 2.0 - e + float(rng.uniform(0.3, 0.7)) * (e - 2.0)) if ends != "out" else full_hi
    zlo = -22.0 + j * float(rng.uniform(0.3, 0.7)) if ends != "in" else full_lo
    return dict(seed=seed, inside=inside, starts=starts, pitch=pitch, lead=round(starts * pitch, 4),
                hand=("right", "left")[(seed // 3) % 2], e=e, j=j, root=root, start=start,
                base=round(float(rng.uniform(0.0, 360.0)), 2), z=(round(zlo, 3), round(zhi, 3)),
                clear=bore - 2.0 if inside else bar + 4.0, bore=bore, bar=bar)


def g33_setup(c: dict) -> str:
    stock = (f'shape = "revolve"\nprofile = [[{c["bore"] / 2}, 0], [18, 0], [18, -30], [{c["bore"] / 2}, -30]]'
             if c["inside"] else f'shape = "cylinder"\ndiameter = {c["bar"]}\nz = [-30.0, 0.0]')
    side = '\nside = "inside"' if c["inside"] else ""
    return (f'[machine]\nkind = "lathe"\ndialect = "cnc8x6"\ndiameter_programming = true\n'
            f'start = [{c["clear"]}, 0.0, 20.0]\n[machine.constants]\n8 = {"-" if c["inside"] else ""}130000\n'
            f'[stock]\n{stock}\n[[tool]]\nnumber = 1\nkind = "thread"\nangle = 60.0{side}\n'
            f'[simulation]\ntolerance = {TOLERANCE}\n')


def g33_program(c: dict, lead: float) -> str:
    spin = "M03" if c["hand"] == "right" else "M04"
    blocks = [f"G00 G95 T1 D1 S250 {spin}"]
    for k in range(c["starts"]):
        a = (c["base"] + k * 360.0 / c["starts"]) % 360.0
        blocks += [f"G00 X{c['clear']:.4f} Z2.", f"X{c['start']:.4f}",
                   f"G33 Z-22. F{lead:.4f} I{a:.3f} J{c['j']:.2f} E{c['e']:.2f}", '"',
                   f"G00 X{c['clear']:.4f} Z-22.", "Z2."]
    blocks.append("M30")
    return "".join(f"N{10 * (i + 1)} {b}\n" for i, b in enumerate(blocks))


def g33_measure(c: dict, lead: float, tmp_path) -> dict:
    setup = tmp_path / f"g33-{c['seed']}.toml"
    setup.write_text(g33_setup(c))
    res = cutsim.simulate(f"g33-{c['seed']}.nc", str(setup), text=g33_program(c, lead), checks=False)
    return measure_thread(res.part, *c["z"], inside=c["inside"])


@pytest.mark.parametrize("seed", range(6))
def test_g33_lead_over_lead_in_and_runout(seed, tmp_path):
    c = g33_case(seed)
    got = g33_measure(c, c["lead"], tmp_path)
    where = f"case {c}: measured {got['lead']} {got['hand']} {got['starts']}"
    # the range does hold incomplete grooves: roots shallower than the full depth
    r = np.array([r for _, _, r in got["roots"]])
    assert (np.abs(2.0 * r - c["root"]) > 4.0 * TOLERANCE).any(), where
    assert got["lead"] == pytest.approx(c["lead"], abs=LEAD_TOL), where
    assert got["hand"] == c["hand"] and got["starts"] == c["starts"], where
    # the same thread cut with the lead 5 % long measures 5 % long: a check of the lead fails it
    wrong = g33_measure(c, c["lead"] * 1.05, tmp_path)
    assert wrong["lead"] == pytest.approx(1.05 * c["lead"], abs=LEAD_TOL), where
    assert abs(wrong["lead"] - c["lead"]) > LEAD_TOL and wrong["hand"] == c["hand"], where


# ---------------------------------------------------------------------------------------------
# taps (Sinumerik CYCLE840, PIT) to Z-24: the range runs into the incomplete grooves at the bottom. The
# chamfer (3 x pitch from the tip, docs/setup.md) cuts them shallow, and the groove of the next turn
# (to 4 x pitch from the tip) is full depth but lopsided, its root off the helix. The range is 5
# pitches long and takes 1.6 to 1.9 pitches of them (into the chamfer): a minority of displaced
# roots, but within a turn of the middle of the range, where following one groove from the middle
# ran into them (the lead of left-hand taps read 1 to 4 % short)
TAP = """[machine]
kind = "lathe"
dialect = "sinumerik"
diameter_programming = true
start = [60.0, 0.0, 20.0]
[stock]
shape = "revolve"
profile = [[{hole}, 0], [15, 0], [15, -30], [{hole}, -30]]
[[tool]]
number = 2
kind = "tap"
diameter = {d}
pitch = {p}
length = 40.0
[simulation]
tolerance = {tol}
"""


@pytest.mark.parametrize("seed", range(4))
def test_tap_lead_over_the_chamfer(seed, tmp_path):
    rng = np.random.default_rng(100 + seed)
    d = float(rng.choice([6.0, 8.0, 10.0, 12.0]))
    p = round(float(rng.uniform(0.5, min(3.0, d / 4.0))), 2)
    hand = ("right", "left")[seed % 2]
    (tmp_path / "tap.toml").write_text(TAP.format(hole=(d - p) / 2.0, d=d, p=p, tol=TOLERANCE))
    text = (f"N10 T2 D1\nN20 G18 G95 S200 {'M3' if hand == 'right' else 'M4'} F0.2\nN30 G0 X0 Z20\n"
            f"N40 CYCLE840(10, 0, 2, -24, , 0, 0, 0, 1, , {p})\nN50 M30\n")
    res = cutsim.simulate("tap.mpf", str(tmp_path / "tap.toml"), text=text, checks=False)
    zlo = -24.0 + (4.0 - float(rng.uniform(1.6, 1.9))) * p
    z = (zlo, zlo + 5.0 * p)
    got = measure_thread(res.part, *z, inside=True)
    where = f"M{d:g}x{p} {hand} over {z}: measured {got['lead']} {got['hand']}"
    assert min(r for _, _, r in got["roots"]) < d / 2.0 - 4.0 * TOLERANCE, where  # chamfered roots
    assert got["lead"] == pytest.approx(p, abs=LEAD_TOL) and got["hand"] == hand and got["starts"] == 1, where
