"""Golden transcript of the ISO drilling cycles in a Sinumerik program (tests/data/golden/sinumerik/iso/
iso.mpf -> iso.txt, ``cutsim moves`` with the folder's setup.toml). Checked by hand against the ISO
sequence (docs/dialects/sinumerik.md, "The ISO drilling cycles"): G0 to the hole in the plane at the
level the tool stands on, G0 to R, in with G1 to Z, back to the initial level (G98) or to R (G99).

- N30 leaves the tool at Z20: the initial level of the cycle mode begun at N40.
- N40 G99 G81: (10, 10) G0 to R2, G1 to -8 at F120, G0 back to R2 (G99). N50 X25: the same at
  (25, 10), positioned at the R level. N60 G98 Y25: the hole at (25, 25), then G0 up to 20.
- N70 G83 R1 Q5 to -14: strokes of Q 5 from R1: -4, -9, -14; after each, G0 to R1 and G0 down
  to 0.6 mm above the depth reached (-3.4, -8.4); then G0 to 20 (G98).
- N80 G82 X55 Z-6 (R1 kept; P500 is a dwell: no move): G0 (55, 25, 20), to 1, G1 -6, G0 20.
- N90 G99 G85 R2 Z-10 at X70: in and out with G1 at F120 between 2 and -10 (RTP is R: no rapid
  after). N100 G89 at X85: the same (P250 a dwell). N110 G86 at (85, 40): in with G1, out with G0.
- N120 G84 X55 Z-8 F150: in and out at F150 (the F in force: F = pitch x speed), from R2.
- N130 G73 Q3 from R2 to -7: strokes to -1, -4, -7, each after a 1 mm G1 retraction (0, -3),
  then G0 to R2 (G99).
- N140 G80 G0 Z50 ends the mode: a plain rapid; N150 G1 is a plain cut again.

A changed transcript is a changed interpretation: review the diff, then regenerate with
CUTSIM_UPDATE_GOLDEN=1.
"""
from __future__ import annotations

import os
from pathlib import Path

import pytest
from click.testing import CliRunner

from cutsim.cli import main

FOLDER = Path(__file__).resolve().parents[2] / "data" / "golden" / "sinumerik" / "iso"
PROGRAMS = sorted(FOLDER.glob("*.mpf"))


def test_every_program_has_a_golden():
    assert {p.stem for p in PROGRAMS} == {"iso"}


@pytest.mark.parametrize("prog", PROGRAMS, ids=lambda p: p.stem)
def test_iso_transcript(prog):
    res = CliRunner().invoke(main, ["moves", str(prog), "--setup", str(FOLDER / "setup.toml")])
    assert res.exit_code == 0, res.output
    golden = prog.with_suffix(".txt")
    if os.environ.get("CUTSIM_UPDATE_GOLDEN"):
        golden.write_text(res.output)
    assert res.output == golden.read_text()
