"""Property test of the thread gauge on inside threads (tests/support/inside_thread_cases.py):
random single-start ISO metric inside threads, pitch 0.75 to 2.5, diameter 8 P to 60 mm,
either hand. Each program's check (lead, starts, hand, major, minor and pitch diameter both ways,
start phases) is derived from its words; the correct part passes, and each wrong one fails on the
item that is wrong: the last pass 0.04 shallower (major and pitch diameters), one start 10 degrees
late (its phase), the wrong spindle direction (hand), the lead 1 % long (lead).

Five simulations a case (about 30 s); 2 cases run in the default suite, 28 more under ``slow``."""
import pytest

import cutsim
from cutsim.reports.checks import evaluate, format_failures
from cutsim.testing import make_check_spec
from support.inside_thread_cases import VARIANTS, make_case

WRONG = {"shallow": {"major_diameter", "pitch_diameter", "pitch_diameter_wires"}, "hand": {"hand"}, "pitch": {"lead"}}


def _verify(seed, tmp_path):
    case = make_case(seed)
    setup = tmp_path / f"inside{seed}.toml"
    setup.write_text(case.setup())
    where = f"case {seed} (P {case.pitch}, {case.starts} start(s), {case.hand}, X {case.x_last}):\n"
    for v in VARIANTS:
        r = cutsim.simulate(f"inside{seed}-{v}.nc", str(setup), text=case.program(v), checks=False)
        rec = evaluate(make_check_spec(r, case.check()), r)
        failed = {i["quantity"] for i in rec["items"] if not i["passed"]}
        if v == "ok":
            assert rec["passed"], where + case.program() + format_failures([rec])
            continue
        want = WRONG.get(v, {f"phase[{seed % case.starts + 1}]"})
        assert want <= failed, where + f"the {v} variant failed on {failed}, not {want}:\n" + case.program(v)


@pytest.mark.parametrize("seed", range(2))
def test_inside_thread_verdicts(seed, tmp_path):
    _verify(seed, tmp_path)


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(2, 30))
def test_inside_thread_verdicts_all(seed, tmp_path):
    _verify(seed, tmp_path)
