"""Property test of the thread check over random lathe programs (tests/support/thread_cases.py): a bar
turned to a diameter, then 1-3 starts of a thread (random lead, start Z, start angle, hand, 1-3
passes, turning and thread tools with and without nose radii) in CNC8x6 or ISG. Each program's
check is derived from its words; the correct part must pass it, and each deliberately wrong part
(lead 1 % long, one start 10 degrees late, root 0.05 mm too deep) must fail it, on the item that
is wrong.

500 cases, seeds 0-499. Every fifth (100 cases, 400 simulations) runs in the default suite; the
other 400 are marked ``slow``: ``pytest -m "slow or not slow" tests/reports/test_thread_check_props.py``
runs all 500.
"""
import pytest

import cutsim
from cutsim.reports.checks import evaluate, format_failures
from cutsim.testing import make_check_spec
from support.thread_cases import VARIANTS, make_case

CASES = 500
DEFAULT = [s for s in range(CASES) if s % 5 == 0]
SLOW = [s for s in range(CASES) if s % 5 != 0]
WRONG_ITEM = {"lead": "lead", "deep": "root_diameter"}  # "shift": the shifted start's phase item


def _records(seed, tmp_path):
    case = make_case(seed)
    setup = tmp_path / f"case{seed}.toml"
    setup.write_text(case.setup())
    out = {}
    for v in VARIANTS:
        r = cutsim.simulate(f"case{seed}-{v}.nc", str(setup), text=case.program(v), checks=False)
        out[v] = evaluate(make_check_spec(r, case.check()), r)
    return case, out


def _verify(seed, tmp_path):
    case, recs = _records(seed, tmp_path)
    where = f"case {seed} ({case.dialect}, {case.starts} start(s), {case.hand}, lead {case.lead}):\n"
    assert recs["ok"]["passed"], where + case.program() + format_failures([recs["ok"]])
    for v in VARIANTS[1:]:
        rec = recs[v]
        assert not rec["passed"], where + f"the {v} variant passed:\n" + case.program(v)
        failed = {i["quantity"] for i in rec["items"] if not i["passed"]}
        want = WRONG_ITEM.get(v, f"phase[{seed % case.starts + 1}]")
        assert want in failed, where + f"the {v} variant failed on {failed}, not {want}"


@pytest.mark.parametrize("seed", DEFAULT)
def test_thread_check_verdicts(seed, tmp_path):
    _verify(seed, tmp_path)


@pytest.mark.slow
@pytest.mark.parametrize("seed", SLOW)
def test_thread_check_verdicts_all(seed, tmp_path):
    _verify(seed, tmp_path)
