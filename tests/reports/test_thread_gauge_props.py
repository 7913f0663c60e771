"""Property test of the thread gauge (tests/support/gauge_cases.py): random single-start ISO
metric threads, inside (even seeds) and outside (odd), pitch 0.75 to 2.5, diameter 8 P to 60 mm,
either hand, cut with a full-profile insert. Each program's check (lead, starts, hand, major, minor
and pitch diameter both ways, start phase) is derived from its words; the correct part passes,
and each wrong one fails on the item that is wrong: the last pass 0.04 shallow (pitch diameters
and the diameter the tip forms), the start 10 degrees late (its phase), M03/M04 swapped (hand),
the lead 1 % long (lead).

Even seeds are inside, odd outside; seeds 0, 1 (mod 4) CNC8x6 (G33 ... I F), 2, 3 ISG (G33 ... K
S.OFFSET=). Five simulations a case; 4 cases (inside and outside in both dialects) run in the
default suite, 36 more under ``slow``."""
import pytest

import cutsim
from cutsim.reports.checks import evaluate, format_failures
from cutsim.testing import make_check_spec
from support.gauge_cases import VARIANTS, make_case


def _verify(seed, tmp_path):
    case = make_case(seed)
    setup = tmp_path / f"gauge{seed}.toml"
    setup.write_text(case.setup())
    where = f"case {seed} ({case.dialect}, {case.side}, P {case.pitch}, {case.hand}, X {case.x_last}):\n"
    for v in VARIANTS:
        r = cutsim.simulate(f"gauge{seed}-{v}.nc", str(setup), text=case.program(v), checks=False)
        rec = evaluate(make_check_spec(r, case.check()), r)
        failed = {i["quantity"] for i in rec["items"] if not i["passed"]}
        if v == "ok":
            assert rec["passed"], where + case.program() + format_failures([rec])
        else:
            want = case.wrong_items(v)
            assert want <= failed, where + f"the {v} variant failed on {failed}, not {want}:\n" + case.program(v)


@pytest.mark.parametrize("seed", range(4))
def test_thread_gauge_verdicts(seed, tmp_path):
    _verify(seed, tmp_path)


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(4, 40))
def test_thread_gauge_verdicts_all(seed, tmp_path):
    _verify(seed, tmp_path)
