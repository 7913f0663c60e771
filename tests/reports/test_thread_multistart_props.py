"""Property test of the thread gauge on multi-start threads (tests/support/multistart_cases.py):
2, 3 and 4 starts cut one after the other with a sharp 60 degree V, inside and outside, either
hand, random pitch, diameter and start phase, at tolerance 0.002. Every start's grooves are
swept with stations of their own; the gauge measures each groove in a section beside one of its
own start's stations (docs/checks.md, "Inside threads, major, minor and pitch diameters"), so the
pitch diameter both ways equals the program's d2 = d - 0.649519 P within the check's tolerance of
0.002 mm (measured: within 0.2 um; reading every groove in the sections of one start's stations
gave 1.8 to 3.4 um small). The wrong parts fail the item that is wrong: one start 10 degrees late
(its phase), the last passes 0.01 mm short of the depth (both pitch diameters, 0.02 off).

Three simulations a case; 3 cases (2, 3 and 4 starts) run in the default suite, 9 more under
``slow``. The check measures in 12 directions (``angles``) to keep the runs short."""
import pytest

import cutsim
from cutsim.reports.checks import evaluate, format_failures
from cutsim.testing import make_check_spec
from support.multistart_cases import VARIANTS, make_case


def _verify(seed, tmp_path):
    case = make_case(seed)
    setup = tmp_path / f"multi{seed}.toml"
    setup.write_text(case.setup())
    where = f"case {seed} ({case.side}, P {case.pitch}, {case.starts} starts, {case.hand}, d {case.d}):\n"
    for v in VARIANTS:
        r = cutsim.simulate(f"multi{seed}-{v}.nc", str(setup), text=case.program(v), checks=False)
        rec = evaluate(make_check_spec(r, dict(case.check(), angles=12)), r)
        items = {i["quantity"]: i for i in rec["items"]}
        failed = {k for k, i in items.items() if not i["passed"]}
        if v == "ok":
            assert rec["passed"], where + case.program() + format_failures([rec])
            for k in ("pitch_diameter", "pitch_diameter_wires"):
                assert abs(items[k]["measured"] - case.pitch_diameter) <= 0.002, (where, k, items[k])
        else:
            want = case.wrong_items(v)
            assert want <= failed, where + f"the {v} variant failed on {failed}, not {want}:\n" + case.program(v)


@pytest.mark.parametrize("seed", range(3))
def test_multistart_pitch_diameter(seed, tmp_path):
    _verify(seed, tmp_path)


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(3, 12))
def test_multistart_pitch_diameter_all(seed, tmp_path):
    _verify(seed, tmp_path)
