"""G76 (LinuxCNC's threading cycle) against positions worked out by hand from its rules
(docs/dialects/rs274ngc.md, "G76"); test_rs274ngc_oracle.py compares it with rs274 move by move."""
from __future__ import annotations

import json
import math
import random
from pathlib import Path

import pytest
from click.testing import CliRunner

from cutsim.cli import main
from cutsim.interp import interpret
from cutsim.interp.canon import Feed, Rapid, SyncedFeed
from cutsim.interp.errors import CutsimError
from cutsim.interp.core.modal import InterpConfig

START = "G21 G18 G90\nS300 M3\nG0 X12 Z5\n"


def moves(text: str):
    prog = interpret("t.ngc", text, InterpConfig(dialect="rs274ngc", machine_kind="lathe"))
    return [r for r in prog.records if isinstance(r, (Rapid, Feed, SyncedFeed))]


def passes(ms):
    """The moves after the approach, cut into passes (each begins with the rapid back)."""
    body = ms[1:-1]  # the approach G0 and the final rapid to the block's end
    out, cur = [], []
    for r in body:
        if isinstance(r, Rapid) and cur and isinstance(cur[-1], Rapid) and len(cur) > 1:
            out.append(cur)
            cur = []
        cur.append(r)
    return out + [cur]


def test_plain_passes_at_the_depths_of_j_times_the_pass_number():
    # I-1: crest at X11; J0.2, K1: depths 1.2, 1.4, ... below the drive line X12 while short of
    # 2.0, then 2.0 once; retract line X12 + (2.0 - depth); thread to Z-20 at 1.5 mm/rev
    ms = moves(START + "G76 P1.5 Z-20 I-1 J0.2 K1\nM2\n")
    ps = passes(ms)
    depths = [12 - p[1].end[0] for p in ps]
    assert depths == pytest.approx([1.2, 1.4, 1.6, 1.8, 2.0])
    for p, d in zip(ps, depths):
        back, into, thread, out = p
        assert back.end == pytest.approx((12 + 2.0 - d, 0, 5))
        assert into.end == pytest.approx((12 - d, 0, 5))
        assert isinstance(thread, SyncedFeed) and thread.lead == 1.5 and thread.lead_axis == "Z"
        assert thread.start_angle == 0.0 and thread.end == pytest.approx((12 - d, 0, -20))
        assert out.end == pytest.approx((12 + 2.0 - d, 0, -20))
    assert ms[-1].end == pytest.approx((12, 0, -20))  # the block's end point, X where it started


def test_degression_spring_passes_and_a_bore():
    # I+0.5: a bore, cut outwards from X12; R2: depth 0.5 + 0.3 * sqrt(n) while short of 0.5 + 1.1;
    # H2: the full depth three times
    ms = moves(START + "G76 P2 Z-10 I0.5 J0.3 K1.1 R2 H2\nM2\n")
    xs = [p[1].end[0] - 12 for p in passes(ms)]
    n_max = max(n for n in range(1, 50) if 0.3 * math.sqrt(n) < 1.1)
    want = [0.5 + 0.3 * math.sqrt(n) for n in range(1, n_max + 1)] + [1.6] * 3
    assert xs == pytest.approx(want)


def test_compound_angle_moves_each_pass_back_along_the_flank_and_the_last_ends_at_z():
    t = math.tan(math.radians(30))
    ps = passes(moves(START + "G76 P1.5 Z-20 I-1 J0.25 K1 Q30\nM2\n"))
    for p in ps:
        d = 12 - p[1].end[0]
        zoff = (d - 1) * t
        assert p[1].end[2] == pytest.approx(5 - zoff)
        assert p[2].end[2] == pytest.approx(-20 + 1 * t - zoff)
    assert ps[-1][2].end[2] == pytest.approx(-20)


def test_tapers_keep_the_lead_along_z_and_chain_the_spindle_angle():
    # E2 L3: entry taper from 1 (K) above the pass depth to it over 2 mm of Z, exit taper back up.
    # LinuxCNC syncs the path: the taper's path lead is 1.5 * hypot(2, 1) / 2, so along Z it
    # advances 1.5 per revolution like the thread
    ms = moves(START + "G76 P1.5 Z-20 I-1 J0.5 K1 E2 L3\nM2\n")
    p = passes(ms)[-1]  # full depth 2: crest X11, root X10
    back, radial, ramp_in, thread, ramp_out, out = p
    taper_lead = 1.5 * math.hypot(2, 1) / 2
    assert back.end == pytest.approx((12, 0, 5))
    assert radial.end == pytest.approx((11, 0, 5)) and radial.lead_axis == "X" and radial.lead == pytest.approx(taper_lead)
    assert radial.start_angle == 0.0
    assert ramp_in.end == pytest.approx((10, 0, 3)) and ramp_in.lead_axis == "Z" and ramp_in.lead == pytest.approx(1.5)
    assert ramp_in.start_angle == pytest.approx(360.0 * 1 / taper_lead % 360)
    turns = 1 / taper_lead + math.hypot(2, 1) / taper_lead
    assert thread.start_angle == pytest.approx(360.0 * turns % 360)
    assert thread.end == pytest.approx((10, 0, -18)) and thread.lead == 1.5
    assert ramp_out.end == pytest.approx((11, 0, -20)) and ramp_out.lead == pytest.approx(1.5)
    assert out.end == pytest.approx((12, 0, -20))


def test_g7_reads_i_j_k_as_diameters_and_e_as_a_length():
    plain = moves(START + "G76 P1.5 Z-20 I-1 J0.2 K1 E2 L1\nM2\n")
    g7 = moves("G21 G18 G90\nS300 M3\nG7\nG0 X24 Z5\nG76 P1.5 Z-20 I-2 J0.4 K2 E2 L1\nM2\n")
    assert [r.end for r in g7] == [pytest.approx(r.end) for r in plain]


def test_increasing_z_flips_the_compound_angle_and_the_tapers():
    t = math.tan(math.radians(29.5))
    ps = passes(moves(START + "G76 P1 Z30 I-1 J0.5 K1 Q29.5 E2 L2\nM2\n"))
    last = ps[-1]
    assert last[1].end[2] == pytest.approx(5 + t)  # the start moves back towards -Z
    assert last[2].end == pytest.approx((10, 0, 30 - 1 * t + t - 2))  # thread ends E before the end
    assert last[3].end == pytest.approx((11, 0, 30))


@pytest.mark.parametrize("seed", range(20))
def test_random_blocks_reach_the_full_depth_and_never_cut_deeper(seed):
    rng = random.Random(seed)
    i = rng.choice([-1, 1]) * rng.uniform(0.2, 2)
    j = rng.uniform(0.05, 0.5)
    k = j + rng.uniform(0.1, 1.5)
    z = rng.choice([-1, 1]) * rng.uniform(5, 30) + 5
    block = (f"G76 P{rng.uniform(0.5, 3):.3f} Z{z:.3f} I{i:.4f} J{j:.4f} K{k:.4f} R{rng.uniform(1, 3):.2f} "
             f"Q{rng.uniform(0, 30):.1f} H{rng.randint(0, 2)} E{rng.uniform(0, 3):.2f} L{rng.randint(0, 3)}")
    ms = moves(START + block + "\nM2\n")
    side = 1 if i > 0 else -1
    depth = [side * (r.end[0] - 12) for r in ms if isinstance(r, SyncedFeed)]
    full = abs(float(f"{i:.4f}")) + float(f"{k:.4f}")
    assert max(depth) == pytest.approx(full, abs=1e-9)
    assert all(d <= full + 1e-9 for d in depth)
    assert all(r.lead > 0 for r in ms if isinstance(r, SyncedFeed))


@pytest.mark.parametrize("block, message", [
    ("G76 Z-20 I-1 J0.2 K1", "pitch P"), ("G76 P1.5 Z-20 J0.2 K1", "I, J and K"),
    ("G76 P1.5 Z-20 I0 J0.2 K1", "I not 0"), ("G76 P1.5 Z-20 I-1 J0 K1", "J more than 0"),
    ("G76 P1.5 Z-20 I-1 J0.2 K0.2", "K more than J"), ("G76 P0 Z-20 I-1 J0.2 K1", "more than 0"),
    ("G76 P1.5 I-1 J0.2 K1", "all axes missing"), ("G76 P1.5 Z-20 I-1 J0.2 K1 H0.5", "whole number"),
    ("G76 P1.5 Z-20 I-1 J0.2 K1 L-1", "negative"), ("M5\nG76 P1.5 Z-20 I-1 J0.2 K1", "spindle not turning"),
    ("G76 P1.5 Z-20 I-1 J0.2 K1\nZ-10", "pitch P"),  # G76 stays the motion mode, its words do not
])
def test_refused_blocks(block, message):
    with pytest.raises(CutsimError, match=message):
        moves(START + block + "\nM2\n")


EXAMPLE = Path(__file__).resolve().parents[3] / "examples" / "rs274ngc" / "g76-tapers"


@pytest.mark.parametrize("spoil, failing", [
    # E2 L0: no tapers (the thread runs at full depth to both ends), and no radial synchronised move
    # before it: the groove lies 1.5 * 0.605649 = 0.908 mm (218 degrees) off
    ("E2 L3", {"entry taper", "exit taper", "M20x1.5 by G76"}),
    # Q0: every pass starts at Z-4, the groove and the entry taper 0.52 mm off (the exit ends at Z-30 still)
    ("Q29.5", {"M20x1.5 by G76", "entry taper"}),
])
def test_the_example_checks_fail_on_a_spoiled_block(tmp_path, spoil, failing):
    # the example's own checks pass (tests/app/test_examples.py); here the block is spoiled and the
    # checks that measure what was spoiled must fail
    text = (EXAMPLE.with_suffix(".nc")).read_text()
    text = text.replace(spoil, {"E2 L3": "E2 L0", "Q29.5": "Q0"}[spoil])
    prog = tmp_path / "g76-tapers.nc"
    prog.write_text(text)
    setup = tmp_path / "g76-tapers.toml"
    setup.write_text(EXAMPLE.with_suffix(".toml").read_text().replace('"tools-thread.tbl"', f'"{EXAMPLE.parent / "tools-thread.tbl"}"'))
    res = CliRunner().invoke(main, ["simulate", str(prog), "--setup", str(setup), "--out", str(tmp_path / "out"), "-q"])
    report = json.loads((tmp_path / "out" / "report.json").read_text())
    failed = {c["name"] for c in report["checks"] if not c["passed"]}
    assert failed == failing, res.output
