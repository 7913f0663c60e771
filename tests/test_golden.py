"""Golden transcripts: the canonical moves (``cutsim moves``) of the CNC8x6 seed examples.

The files in tests/golden/ were checked by hand against the manuals and conventions.md, e.g.
multipass: the default start is 5 mm outside the 27 mm blank and 5 mm above it, (37, 5);
lead-in: the thread ends at X 71.798 - 2*12*tan(18 deg) = 63.999927; runout-parameter: at
X 64 + 2*12*tan(20 deg) = 72.735286; large-lead: LEAD 250 from R10. A changed transcript is a
changed interpretation: review the diff, then regenerate with CUTSIM_UPDATE_GOLDEN=1.
"""
from __future__ import annotations

import os
from pathlib import Path

import pytest
from click.testing import CliRunner

from conftest import EXAMPLES
from cutsim.cli import main

GOLDEN = Path(__file__).parent / "golden"
NAMES = ["multipass", "start-offset", "lead-in", "runout-constant", "runout-parameter", "taper", "large-lead"]


@pytest.mark.parametrize("name", NAMES)
def test_cnc8x6_transcript(name):
    prog = EXAMPLES / "cnc8x6-lathe" / f"{name}.nc"
    res = CliRunner().invoke(main, ["moves", str(prog), "--setup", str(prog.with_suffix(".toml"))])
    assert res.exit_code == 0, res.output
    golden = GOLDEN / f"cnc8x6_{name}.txt"
    if os.environ.get("CUTSIM_UPDATE_GOLDEN"):
        golden.write_text(res.output)
    assert res.output == golden.read_text()


def test_cnc8x6_helix_transcript():
    """Seed 002: 21 full clockwise circles about (100, 0), each rising 1.05 (N50 run 21 times by
    G73 L50 Q20), the half circle N60 to (200, 0, 22.575), then the N80 rapid to (100, 0, 40)."""
    prog = EXAMPLES / "cnc8x6-mill" / "helix.nc"
    res = CliRunner().invoke(main, ["moves", str(prog), "--setup", str(prog.with_suffix(".toml"))])
    assert res.exit_code == 0, res.output
    golden = GOLDEN / "cnc8x6_helix.txt"
    if os.environ.get("CUTSIM_UPDATE_GOLDEN"):
        golden.write_text(res.output)
    assert res.output == golden.read_text()
