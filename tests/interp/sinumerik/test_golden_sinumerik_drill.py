"""Golden transcripts of the Sinumerik drilling cycles (tests/data/golden/sinumerik/drill/NAME.mpf ->
NAME.txt, ``cutsim moves`` with the folder's setup.toml). Each was checked by hand against the
cycle manuals' sequences (docs/dialects/sinumerik.md, "Drilling cycles"):

- cycle81-82: G0 from Z30 straight to RFP + SDIS = 2, G1 to DP -12, G0 to RTP 10; CYCLE82 with DPR
  8.5 below RFP 0 reaches -8.5 from the safety plane 3 (DTB is a dwell: no move); DP -30 and DPR 10
  together: DPR wins, -1 - 10 = -11, from RFP + SDIS = -1 + 1 = 0, out to RTP 5.
- cycle83: FDPR 10, DAM 3 to -25 gives strokes 10, 7, 4 (each the last less DAM while above DAM),
  then DAM 3 is due with 4 left (< 2 x 3): two strokes of 2, so -10, -17, -21, -23, -25; the first
  at F 100 x FRF 0.6 = 60; chip removal back to 2 and down again to 0.6 above the depth reached
  (the anticipation distance up to 30 mm). Chip breaking to -17 with FDPR 8, DAM 3: 8, 5, then 4
  left < 6: 2 and 2, each stroke after a 1 mm G1 retraction. The 17-parameter form: FDEP -5
  absolute, DAM 0 (strokes of 5), _MDEP 5, _VRT 0.5: -5, back to -4.5, -10, back to -9.5, -12.
  _DIS1 1 with FDEP -15 to -40: strokes 15, 15, 10, re-entering at -14 and -29.
- tapping: MPIT 10 = M10 taps at 1.5 mm per revolution in and out to RFP + SDIS; PIT -1.25 (a
  left-hand thread) at 1.25/rev to DPR 12; CYCLE840 without encoder (ENC 1) at the F in force 100;
  with encoder (ENC 0) at PIT 1.75/rev; the G1 after it at F200 per minute again.
- boring: CYCLE85 in at FFR 60, out at RFF 250; CYCLE86 in at F90 and out with G0 along the axis
  (the lift-off is not simulated); CYCLE87 and CYCLE88 in at F90, G0 to RTP; CYCLE89 in and out
  at F90.
- patterns: MCALL runs CYCLE81 after N50 and N60 (not after the MCALL block N40); HOLES1 from
  (10, 10) at 0 degrees, 5 then 10 apart: X15, 25, 35 (the first hole is nearer to (20, 90) than the
  last); HOLES2 about (70, 70) radius 15 from 0 degrees every 90: (85, 70), (70, 85), (55, 70),
  (70, 55); CYCLE801 3 x 2 from (30, 40), 10 along X and 8 along Y, the second row backwards,
  with the new modal CYCLE81 (RTP 8, SDIS 1, DP -3); after MCALL alone N130 only moves.

A changed transcript is a changed interpretation: review the diff, then regenerate with
CUTSIM_UPDATE_GOLDEN=1.
"""
from __future__ import annotations

import os
from pathlib import Path

import pytest
from click.testing import CliRunner

from cutsim.cli import main

FOLDER = Path(__file__).resolve().parents[2] / "data" / "golden" / "sinumerik" / "drill"
PROGRAMS = sorted(FOLDER.glob("*.mpf"))


def test_every_program_has_a_golden():
    assert {p.stem for p in PROGRAMS} == {"cycle81-82", "cycle83", "tapping", "boring", "patterns"}


@pytest.mark.parametrize("prog", PROGRAMS, ids=lambda p: p.stem)
def test_drilling_transcript(prog):
    res = CliRunner().invoke(main, ["moves", str(prog), "--setup", str(FOLDER / "setup.toml")])
    assert res.exit_code == 0, res.output
    golden = prog.with_suffix(".txt")
    if os.environ.get("CUTSIM_UPDATE_GOLDEN"):
        golden.write_text(res.output)
    assert res.output == golden.read_text()
