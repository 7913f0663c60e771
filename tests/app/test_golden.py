"""Golden transcripts: the canonical moves (``cutsim moves``) of the CNC8x6 seed examples.

The files in tests/data/golden/<dialect>/ were checked by hand against the manuals and conventions.md, e.g.
multipass: the default start is 5 mm outside the 27 mm blank and 5 mm above it, (37, 5);
lead-in: the thread ends at X 71.798 - 2*12*tan(18 deg) = 63.999927; runout-parameter: at
X 64 + 2*12*tan(20 deg) = 72.735286; large-lead: LEAD 250 from R10. A changed transcript is a
changed interpretation: review the diff, then regenerate with CUTSIM_UPDATE_GOLDEN=1.

The manuals' programs live in ../shared (skipped without it, see conftest.py). The repository's
own examples (examples/, always run) have golden files ``own_<folder>_<name>.txt``, checked by
hand against their programs: e.g. two-start-checked ends each pass at X = X0 - 2*8*tan 15 deg +
2*6*tan 15 deg (37.8332 -> 36.761403), runout-const at 36.933 + 2*5*tan 30 deg = 42.706503,
leadin-param reaches 54.6043 - 2*10*tan 22.5 deg = 46.320029, helix-groove falls 2 per circle
from Z1 to Z-11 and to Z-12 on the half circle, and the plate's POCKET1 finishes on the tool-centre
rectangle X20..50 Y30..50 with corner radius 1 (40 x 30, radius 6, minus the 5 mm tool radius).
Every other Sinumerik example has one too: POCKET4 (PRAD 15, 10 mm tool, FAL 0.2) roughs the
circles of radius 4.5 (0.9 tool radii) and 9.8 and finishes on radius 10 about (40, 40); CYCLE71
(80 x 50, _MIDA 7) cuts ceil(50 / 7) + 1 = 9 lines 6.25 apart from X -10 (_FDP 5 + tool radius) to
87 (_FDP1 2 + tool radius) at Z 1 and Z 0 (_MID 1 from _RFP 2). CYCLE97 (cycle97-m30x2) makes its
first cut at radius 15 - 1.177 sqrt(1/5) = 14.47363, shifted (1.227 - 0.52637) tan 29 = 0.388365
towards +Z, its chained G33 blocks all starting at 30 degrees (4 and 24 mm are whole turns of lead
4), the last cut of start 2 at radius 13.773 from Z4 at 210 degrees. turning-cycles roughs with
CYCLE95 at radius 20 - 8.8 k / 5 (18.24 first) from Z1.1 (_VRT 1 + FALZ 0.1), cuts the DIN 76
undercut down the 30 degree flank from (12, -19.5) to (9.8, -23.310512) and round the fillet 1.6
about (11.4, -28.4), the DIN 509 one from (16, -42.5) to (15.7, -43.619615) and round (16.3, -44.4).
The RS274NGC g71-shaft roughs from the line S (16, 2) - P0 + D (6.2, 0): the pass at X14.5 from Z 2 - 2 x 1.5 / 9.8 = 1.693878 to the
shoulder's offset Z-31.8, back 0.5 (R) in X and Z.

The test programs under tests/data/programs/ that simulate (CNC8x6 and ISG) have golden files
``tests_<folder>_<name>.txt`` with the setup their tests use (TEST_PROGRAMS), e.g. mill/slot.nc
goes down to Z-3 at (20, 50) and cuts to X80 at F200.
"""
from __future__ import annotations

import os
from pathlib import Path

import pytest
from click.testing import CliRunner

from conftest import EXAMPLES, REPO_EXAMPLES
from cutsim.cli import main

GOLDEN = Path(__file__).resolve().parents[1] / "data" / "golden"
# the dialect folder of a test program's golden file, by the folder the program is in
TEST_DIALECTS = {"checks": "cnc8x6", "isg": "isg", "mill": "cnc8x6"}


def own_golden(prog: Path) -> Path:
    """The golden file of an example (examples/<dialect>[-kind]/<name>): by its folder's dialect."""
    return GOLDEN / prog.parent.name.split("-")[0] / f"own_{prog.parent.name}_{prog.stem}.txt"


NAMES = ["multipass", "start-offset", "lead-in", "runout-constant", "runout-parameter", "taper", "large-lead"]


@pytest.mark.parametrize("name", NAMES)
def test_cnc8x6_transcript(name):
    prog = EXAMPLES / "cnc8x6-lathe" / f"{name}.nc"
    res = CliRunner().invoke(main, ["moves", str(prog), "--setup", str(prog.with_suffix(".toml"))])
    assert res.exit_code == 0, res.output
    golden = GOLDEN / "cnc8x6" / f"cnc8x6_{name}.txt"
    if os.environ.get("CUTSIM_UPDATE_GOLDEN"):
        golden.write_text(res.output)
    assert res.output == golden.read_text()


def test_cnc8x6_helix_transcript():
    """Seed 002: 21 full clockwise circles about (100, 0), each rising 1.05 (N50 run 21 times by
    G73 L50 Q20), the half circle N60 to (200, 0, 22.575), then the N80 rapid to (100, 0, 40)."""
    prog = EXAMPLES / "cnc8x6-mill" / "helix.nc"
    res = CliRunner().invoke(main, ["moves", str(prog), "--setup", str(prog.with_suffix(".toml"))])
    assert res.exit_code == 0, res.output
    golden = GOLDEN / "cnc8x6" / "cnc8x6_helix.txt"
    if os.environ.get("CUTSIM_UPDATE_GOLDEN"):
        golden.write_text(res.output)
    assert res.output == golden.read_text()


OWN = sorted(p for p in REPO_EXAMPLES.rglob("*") if p.suffix in (".nc", ".mpf")
             and own_golden(p).is_file())


def test_own_examples_have_transcripts():
    """Every example program has a golden transcript."""
    want = {p for p in REPO_EXAMPLES.rglob("*") if p.suffix in (".nc", ".mpf")}
    assert want <= set(OWN), sorted(str(p) for p in want - set(OWN))


@pytest.mark.parametrize("prog", OWN, ids=lambda p: f"{p.parent.name}/{p.stem}")
def test_own_example_transcript(prog):
    res = CliRunner().invoke(main, ["moves", str(prog), "--setup", str(prog.with_suffix(".toml"))])
    assert res.exit_code == 0, res.output
    golden = own_golden(prog)
    if os.environ.get("CUTSIM_UPDATE_GOLDEN"):
        golden.write_text(res.output)
    assert res.output == golden.read_text()


TESTS = Path(__file__).resolve().parents[1] / "data" / "programs"
# test programs that simulate, with the setup their tests use (the others are error cases)
TEST_PROGRAMS = {
    "checks/multipass.nc": "checks/multipass.toml", "checks/multipass-shallow.nc": "checks/multipass.toml",
    "checks/slot.nc": "checks/slot.toml", "checks/slot-shallow.nc": "checks/slot.toml",
    "checks/slot-deep.nc": "checks/slot.toml",
    "isg/three-start.nc": "isg/three-start.toml", "isg/offset90.nc": "isg/three-start.toml",
    "mill/ball.nc": "mill/plate.toml", "mill/pocket.nc": "mill/plate.toml", "mill/slot.nc": "mill/plate.toml",
    "mill/warnings.nc": "mill/plate.toml",
}


@pytest.mark.parametrize("rel", sorted(TEST_PROGRAMS))
def test_test_program_transcript(rel):
    prog = TESTS / rel
    res = CliRunner().invoke(main, ["moves", str(prog), "--setup", str(TESTS / TEST_PROGRAMS[rel])])
    assert res.exit_code == 0, res.output
    golden = GOLDEN / TEST_DIALECTS[prog.parent.name] / f"tests_{prog.parent.name}_{prog.stem}.txt"
    if os.environ.get("CUTSIM_UPDATE_GOLDEN"):
        golden.write_text(res.output)
    assert res.output == golden.read_text()
