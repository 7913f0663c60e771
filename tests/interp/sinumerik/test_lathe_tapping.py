"""CYCLE840 (tapping with compensating chuck) on a lathe: the tap along Z on the spindle axis,
synchronised with the spindle both ways (interp/sinumerik/turning.py ``compensated_tap``,
docs/dialects/sinumerik-turning.md "Drilling cycles on a lathe"). The numbers are derived here: the
lead from MPIT / PIT or from the feed (F per revolution, F / S per minute), the spindle angle at the
bottom 360 x travel / lead, the way out on the same helix with the spindle reversed; the thread is
measured on the part.
"""
from __future__ import annotations

import pytest
from pathlib import Path

import cutsim
from cutsim.interp.canon import SyncedFeed
from cutsim.reports.measure import measure_thread

TAP = """
[machine]
kind = "lathe"
dialect = "sinumerik"
diameter_programming = true
start = [60.0, 0.0, 20.0]
[stock]
shape = "revolve"
profile = [[4.25, 0], [15, 0], [15, -30], [4.25, -30]]
[[tool]]
number = 2
kind = "tap"
diameter = 10.0
pitch = 1.5
length = 25.0
[simulation]
tolerance = 0.01
"""


def run(tmp_path, pre: str, call: str):
    (tmp_path / "setup.toml").write_text(TAP)  # a bar of 30 with its 8.5 tap hole
    text = f"N10 T2 D1\nN20 G18 {pre}\nN30 G0 X0 Z20\nN40 {call}\nN50 M30\n"
    return cutsim.simulate("tap.mpf", str(tmp_path / "setup.toml"), text=text)


def synced(res):
    return [v for r in res.program.records if isinstance(r, SyncedFeed) for v in (r.start[2], r.end[2], r.lead,
                                                                                   r.start_angle)]


def spindle(res):
    return [r.direction for r in res.program.records if r.src.line == 4 and type(r).__name__ == "Spindle"]


@pytest.mark.parametrize("pre, call", [
    ("G95 S200 M3 F0.2", "CYCLE840(10, 0, 2, -15, , 0, 0, 0, 0, 10)"),        # with encoder, MPIT 10 (1.5)
    ("G95 S200 M3 F0.2", "CYCLE840(10, 0, 2, -15, , 0, 0, 0, 1, , 1.5)"),     # without encoder, PIT 1.5
    ("G95 S200 M3 F1.5", "CYCLE840(10, 0, 2, -15, , 0, 0, 0, 1)"),           # without: the feed 1.5 / rev
    ("G94 S200 M3 F300", "CYCLE840(10, 0, 2, -15, , 0, 0, 0, 1)"),           # G94: F / S = 300 / 200
])
def test_cycle840_taps_m10_on_the_spindle_axis(tmp_path, pre, call):
    # in from RFP + SDIS = Z2 to -15: 17 / 1.5 = 11 1/3 turns, ending at 120 degrees; out on the same
    # helix with the spindle reversed (SDR 0), starting at -120 = 240; M3 again after (SDAC 0)
    res = run(tmp_path, pre, call)
    assert synced(res) == pytest.approx([2.0, -15.0, 1.5, 0.0, -15.0, 2.0, 1.5, 240.0])
    assert spindle(res) == [1, -1, 1]
    got = measure_thread(res.part, -12.0, -4.0, inside=True)
    assert got["lead"] == pytest.approx(1.5, abs=0.005) and got["hand"] == "right" and got["starts"] == 1
    assert got["root_diameter"] == pytest.approx(10.0, abs=0.03)  # the tap's major diameter


def test_cycle840_left_hand_under_m4_and_sdac(tmp_path):
    # M4 in force: a left-hand thread; SDR 3 backs out under M3; SDAC 5 stops the spindle after
    res = run(tmp_path, "G95 S200 M4 F0.2", "CYCLE840(10, 0, 2, -15, , 0, 3, 5, 0, 10)")
    assert synced(res) == pytest.approx([2.0, -15.0, 1.5, 0.0, -15.0, 2.0, 1.5, 240.0])
    assert spindle(res) == [-1, 1, 0]
    # over -12 .. -4 as the right-hand taps: the range reaches into the grooves the chamfer cut
    # (tests/reports/test_thread_lead_robust.py)
    got = measure_thread(res.part, -12.0, -4.0, inside=True)
    assert got["lead"] == pytest.approx(1.5, abs=0.005) and got["hand"] == "left"
    assert got["root_diameter"] == pytest.approx(10.0, abs=0.03)


def test_iso_g84_on_the_lathe_is_the_compensated_tap(tmp_path):
    # the ISO shell's G84 runs as CYCLE840 with ENC 1: at the feed per revolution F1.5 (G95)
    res = run(tmp_path, "G95 S200 M3 F1.5\nN25 G291", "G84 X0 Z-15 R2 F1.5\nN45 G80\nN46 G290")
    assert synced(res)[:3] + synced(res)[4:7] == pytest.approx([2.0, -15.0, 1.5, -15.0, 2.0, 1.5])


# ---------------------------------------------------------------------------------------------
# SPOS before G331: the spindle positioned, the tap starting at that angle
SPOS = """N10 T2 D1
N20 G18 G95 S200 M3
N30 G0 X0 Z5
N40 SPOS=90
N50 G331 Z-10 K1.5
N60 G332 Z5
N70 SPOS=IC(45)
N80 G331 Z-10 K1.5
N90 G332 Z5
N100 M3
N110 G331 Z-10 K1.5
N120 M30
"""


def test_spos_sets_the_angle_g331_starts_at(tmp_path):
    # SPOS=90: the first G331 starts at 90; 15 / 1.5 = 10 turns later it ends at 90 and G332 starts
    # at -90 = 270. SPOS=IC(45) adds 45 to the last SPOS: 135 (G332 from 225). After M3 the spindle
    # has left its position: a new G331 starts at the zero mark again (cutsim assumes).
    (tmp_path / "setup.toml").write_text(TAP)
    res = cutsim.simulate("spos.mpf", str(tmp_path / "setup.toml"), text=SPOS)
    got = [(r.src.line, r.start_angle) for r in res.program.records if isinstance(r, SyncedFeed)]
    assert got == [(5, 90.0), (6, 270.0), (8, 135.0), (9, 225.0), (11, 0.0)]
    assert not [m for _, m in res.program.warnings if "SPOS" in m]


def test_spos_on_a_mill_warns_once(tmp_path):
    from cutsim import interp_config, load_setup
    from cutsim.interp import interpret

    setup = Path(__file__).parents[2] / "data" / "bad" / "sinumerik" / "setup.toml"
    s = load_setup(str(setup))
    prog = interpret("m.mpf", "G17 G0 X0 Y0 Z5\nSPOS=90\nSPOS=IC(3)\nSPOS[1]=10\nM30\n",
                     interp_config(s, s.machine.start))
    assert sum("SPOS" in m for _, m in prog.warnings) == 1
