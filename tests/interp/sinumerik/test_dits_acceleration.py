"""DITS / DITE = -1 with the machine's acceleration (docs/dialects/sinumerik-turning.md "DITS / DITE",
docs/setup.md `[machine] thread_acceleration`).

The ramp is the path the thread's axis needs to reach its speed v = K S / 60 (mm/s) at the
acceleration a: v^2 / (2 a). Every number below is derived from that by hand: K4 at S300 is
v = 20 mm/s, with a = 200 mm/s^2 the ramp 400 / 400 = 1 mm (S600: v = 40, 1600 / 400 = 4 mm); a
run-in of length L at the lead K turns 2 L / K times (lead change K^2 / (2 L)), the constant-lead
thread behind it lies as if cut from L further back at SF (phase SF + 360 L / K at the Z the cut
starts); a run-out of L over the block's last L mm (lead change -K^2 / (2 L)).
"""
from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner
from hypothesis import given, settings, strategies as st

import cutsim
from cutsim.cli import main
from cutsim.interp import CutsimError, InterpConfig, canon, interpret

EXAMPLE = Path(__file__).resolve().parents[3] / "examples" / "sinumerik" / "thread-two-start"


def run(text: str, acc: float = 0.0) -> canon.Program:
    cfg = InterpConfig(dialect="sinumerik", machine_kind="lathe", start=(50.0, 0.0, 10.0), thread_acceleration=acc)
    return interpret("t.mpf", text, cfg)


def syncs(prog) -> list[tuple]:
    """(start Z, end Z, lead, start angle, lead change) of every thread record."""
    return [(round(r.start[2], 9), round(r.end[2], 9), r.lead, round(r.start_angle, 9), r.lead_change)
            for r in prog.records if isinstance(r, canon.SyncedFeed)]


# K4 from Z4 to Z-20 at SF 45: ramps of 1 mm: the run-in Z4..Z3 (lead change 16 / 2 = 8, 0.5 turns:
# 45 -> 225), the thread Z3..Z-19 (22 / 4 = 5.5 turns: 225 -> 45), the run-out Z-19..Z-20 (-8)
ONE_MM = [(4.0, 3.0, 0.0, 45.0, 8.0), (3.0, -19.0, 4.0, 225.0, 0.0), (-19.0, -20.0, 4.0, 45.0, -8.0)]
THREAD = "G0 X13 Z4\nG33 Z-20 K4 SF=45\nG0 X20\nM30\n"


@pytest.mark.parametrize("words", ["DITS=-1 DITE=-1\n", ""])  # programmed, and the reset value
def test_minus_one_is_the_acceleration_ramp(words):
    prog = run("M3 S300\n" + words + THREAD, acc=200.0)
    assert syncs(prog) == ONE_MM
    assert prog.warnings == []
    assert syncs(run("M3 S300\nDITS=1 DITE=1\n" + THREAD)) == ONE_MM  # the same as programming 1 mm


def test_the_ramp_grows_with_the_square_of_the_speed():
    """S600: v = 40 mm/s, the ramp 4 mm (lead change 16 / 8 = 2, the run-in 2 turns: 45 -> 45; the
    thread Z0..Z-16 4 turns; the run-out from Z-16)."""
    prog = run("M3 S600\nDITS=-1 DITE=-1\n" + THREAD, acc=200.0)
    assert syncs(prog) == [(4.0, 0.0, 0.0, 45.0, 2.0), (0.0, -16.0, 4.0, 45.0, 0.0), (-16.0, -20.0, 4.0, 45.0, -2.0)]


def test_a_programmed_path_longer_than_the_axis_needs_runs_at_the_acceleration():
    """DITS=3 DITE=5 at S300, a = 200: both cut over 1 mm (the manual: a longer path is run at the
    maximum acceleration); DITS=0.5 (shorter: the axis accelerates harder) stays 0.5: the run-in
    Z4..Z3.5, lead change 16, 0.25 turns (45 -> 135), the thread Z3.5..Z-19 5.625 turns (-> 0)."""
    assert syncs(run("M3 S300\nDITS=3 DITE=5\n" + THREAD, acc=200.0)) == ONE_MM
    prog = run("M3 S300\nDITS=0.5 DITE=-1\n" + THREAD, acc=200.0)
    assert syncs(prog) == [(4.0, 3.5, 0.0, 45.0, 16.0), (3.5, -19.0, 4.0, 135.0, 0.0), (-19.0, -20.0, 4.0, 0.0, -8.0)]


def test_without_the_acceleration_a_programmed_minus_one_warns_once():
    """No setup acceleration: -1 cuts no ramp (the thread at its lead from Z4 to Z-20: 6 turns), and
    each word programmed as -1 warns once, at the first thread block it acts on (line 3); two
    chains, one warning each. Never programmed: silent."""
    text = "M3 S300\nDITS=-1 DITE=-1\nG0 X13 Z4\nG33 Z-20 K4 SF=45\nG0 X20\nZ4\nX13\nG33 Z-20 K4\nM30\n"
    prog = run(text)
    assert syncs(prog) == [(4.0, -20.0, 4.0, 45.0, 0.0), (4.0, -20.0, 4.0, 45.0, 0.0)]  # SF stays in force
    msgs = [(src.line, msg) for src, msg in prog.warnings]
    assert msgs == [
        (4, "DITS=-1: the machine's acceleration is not in the setup ([machine] thread_acceleration); the thread is "
            "cut at its lead from the block start"),
        (4, "DITE=-1: the machine's acceleration is not in the setup ([machine] thread_acceleration); the thread is "
            "cut at its lead to the block end")]
    assert run("M3 S300\n" + THREAD).warnings == []


def test_chained_blocks_take_the_run_in_first_and_the_run_out_last():
    """A chain Z4..Z-8 at K4, Z-8..Z-20 at K2 (S300, a = 200): the run-in from the first block's lead
    (1 mm: Z4..Z3, 0.5 turns: 0 -> 180; Z3..Z-8 2.75 turns -> 90), the run-out from the last's: v = 10
    mm/s, 100 / 400 = 0.25 mm (Z-19.75..Z-20, lead change -4 / 0.5 = -8, after 11.75 / 2 = 5.875
    turns: 90 -> 45)."""
    prog = run("M3 S300\nG0 X13 Z4\nG33 Z-8 K4\nG33 Z-20 K2\nG0 X20\nM30\n", acc=200.0)
    assert syncs(prog) == [(4.0, 3.0, 0.0, 0.0, 8.0), (3.0, -8.0, 4.0, 180.0, 0.0), (-8.0, -19.75, 2.0, 90.0, 0.0),
                           (-19.75, -20.0, 2.0, 45.0, -8.0)]


@pytest.mark.parametrize("text,line,col,fragment", [
    ("M3 S600\nDITS=-1\nG0 X13 Z4\nG33 Z0 K4\nM30\n", 4, 8,  # at the lead word K
     "DITS=-1 (the machine's acceleration: 4 mm, v^2 / 2a at the lead 4 mm, S600 and [machine] thread_acceleration "
     "= 200 mm/s^2): the run-in is not shorter than the thread block's 4 mm along Z"),
    ("M3 S600\nDITS=0 DITE=-1\nG0 X13 Z4\nG33 Z1 K4\nG0 X20\nM30\n", 4, 1,
     "DITE=-1 (the machine's acceleration: 4 mm"),
    ("M3 S600\nDITS=0 DITE=9\nG0 X13 Z4\nG33 Z1 K4\nG0 X20\nM30\n", 4, 1,
     "DITE=9 (run at the machine's acceleration: 4 mm"),
])
def test_a_ramp_longer_than_its_block_is_an_error(text, line, col, fragment):
    """As for a programmed ramp: a run-in or run-out not shorter than the block's travel is exit 2 (a
    run-in at the lead word, a run-out at its block)."""
    with pytest.raises(CutsimError) as e:
        run(text, acc=200.0)
    assert (e.value.line, e.value.col) == (line, col) and fragment in str(e.value)


def test_the_setup_key_reaches_the_part_and_the_phase(tmp_path):
    """The example thread-two-start with DITS=-1 DITE=-1 at S300 instead of DITS=1 DITE=2 at S400
    and a = 200 mm/s^2: the run-in is 1 mm again, so its checks (phases SF + 360 DITS / K = 90 and
    270) pass; with a = 100 the run-in is 2 mm and both starts come out 90 degrees late (phase check
    fails), the lead and root unchanged."""
    text = EXAMPLE.with_suffix(".mpf").read_text()
    for old, new in (("DITS=1 DITE=2", "DITS=-1 DITE=-1"), ("S400", "S300")):
        assert old in text
        text = text.replace(old, new)
    base = EXAMPLE.with_suffix(".toml").read_text()
    assert 'dialect = "sinumerik"\n' in base
    for acc, failing in ((200.0, set()), (100.0, {"phase[1]", "phase[2]"})):
        setup = tmp_path / f"s{acc:g}.toml"
        setup.write_text(base.replace('dialect = "sinumerik"\n', f'dialect = "sinumerik"\nthread_acceleration = {acc}\n'))
        res = cutsim.simulate("p.mpf", str(setup), text=text)
        bad = {i["quantity"] for c in res.report["checks"] for i in c["items"] if not i["passed"]}
        assert bad == failing


BAR = """[machine]
kind = "{kind}"
dialect = "{dialect}"
thread_acceleration = {acc}
[stock]
shape = "cylinder"
diameter = 30
z = [-40, 0]
[[tool]]
number = 1
kind = "thread"
angle = 60.0
"""
MILL = """[machine]
kind = "mill"
dialect = "sinumerik"
thread_acceleration = 200
[stock]
shape = "box"
x = [0, 50]
y = [0, 40]
z = [-10, 0]
[[tool]]
number = 1
kind = "endmill"
diameter = 6
"""


@pytest.mark.parametrize("text,fragment", [
    (BAR.format(kind="lathe", dialect="sinumerik", acc=0), "must be more than 0 and at most 1,000,000 mm/s^2"),
    (BAR.format(kind="lathe", dialect="sinumerik", acc=1000001), "must be more than 0"),
    (BAR.format(kind="lathe", dialect="isg", acc=200), 'only for kind = "lathe", dialect = "sinumerik"'),
    (MILL, 'only for kind = "lathe", dialect = "sinumerik"'),
])
def test_bad_thread_acceleration(tmp_path, text, fragment):
    """Exit 2 at the key (line 4, column 1), no traceback."""
    setup = tmp_path / "s.toml"
    setup.write_text(text)
    prog = tmp_path / "p.mpf"
    prog.write_text("G0 X40 Z5\nM30\n")
    res = CliRunner().invoke(main, ["moves", str(prog), "--setup", str(setup)])
    assert res.exit_code == 2 and res.output.startswith(f"{setup}:4:1: error: ") and fragment in res.output, res.output
    assert "Traceback" not in res.output


def test_the_cli_stops_at_a_ramp_too_long(tmp_path):
    setup = tmp_path / "s.toml"
    setup.write_text(BAR.format(kind="lathe", dialect="sinumerik", acc=200))
    prog = tmp_path / "p.mpf"
    prog.write_text("M3 S600\nDITS=-1\nG0 X13 Z4\nG33 Z0 K4\nM30\n")
    res = CliRunner().invoke(main, ["simulate", str(prog), "--setup", str(setup), "--out", str(tmp_path / "o"), "-q"])
    assert res.exit_code == 2 and f"{prog}:4:8: error: DITS=-1 (the machine's acceleration: 4 mm" in res.output
    assert "Traceback" not in res.output


def test_programmed_paths_are_in_the_unit_in_force():
    """The manual: the path is handled according to the dimension setting. G70 DITS=0.1 is 2.54 mm:
    K0.1 (2.54 mm) from Z0.2 (5.08) to Z-1 (-25.4): the run-in 5.08..2.54, lead change 2.54^2 /
    (2 x 2.54) = 1.27. A value programmed in mm stays mm after a later G700 (setting data)."""
    prog = run("M3 S300\nG70 DITS=0.1\nG0 X0.5 Z0.2\nG33 Z-1 K0.1\nM30\n")
    assert [(s, e, lead, round(lc, 9)) for s, e, lead, _, lc in syncs(prog)] == [
        (5.08, 2.54, 0.0, 1.27), (2.54, -25.4, 2.54, 0.0)]
    prog = run("M3 S300\nDITS=0.1\nG700\nG0 X0.5 Z0.2\nG33 Z-1 K0.1\nM30\n")
    assert [(s, e) for s, e, *_ in syncs(prog)] == [(5.08, 4.98), (4.98, -25.4)]


@settings(max_examples=150, deadline=None)
@given(k=st.sampled_from([0.5, 1.0, 1.5, 2.0, 3.5, 6.0]), s=st.integers(50, 2000), a=st.sampled_from([50, 200, 1000, 5000]),
       sf=st.integers(0, 359))
def test_minus_one_over_the_range(k, s, a, sf):
    """K, S, a over the range: L = (K S / 60)^2 / (2 a). A thread Z0..Z-60 with DITS=-1 DITE=-1: the
    run-in ends at Z-L (lead change K^2 / (2 L), SF + 720 L / K after it), the run-out starts at
    Z-(60 - L). A programmed path twice as long cuts the same ramps (run at the acceleration), one
    half as long does not (it stays: the axis accelerates harder)."""
    L = (k * s / 60.0) ** 2 / (2.0 * a)
    text = f"M3 S{s}\nDITS={{}} DITE={{}}\nG0 X13 Z0\nG33 Z-60 K{k:g} SF={sf}\nG0 X20\nM30\n"
    if L >= 30.0 or L < 1e-3:  # the run-in and run-out would overlap (or be under 1 um): not tested here
        return
    prog = run(text.format(-1, -1), acc=a)
    got = syncs(prog)
    flat = [v for g in got for v in g[:3]]
    assert flat == pytest.approx([0.0, -L, 0.0, -L, -(60.0 - L), k, -(60.0 - L), -60.0, k])
    assert [g[4] for g in got] == pytest.approx([k * k / (2 * L), 0.0, -k * k / (2 * L)])
    after = (sf + 720.0 * L / k) % 360.0
    assert abs((got[1][3] - after + 180.0) % 360.0 - 180.0) < 1e-6
    assert syncs(run(text.format(f"{2 * L:.9f}", f"{2 * L:.9f}"), acc=a)) == got
    half = syncs(run(text.format(f"{L / 2:.9f}", f"{L / 2:.9f}"), acc=a))
    assert half[0][1] == pytest.approx(-L / 2, abs=1e-8) and abs(half[0][1] - got[0][1]) > 1e-4
