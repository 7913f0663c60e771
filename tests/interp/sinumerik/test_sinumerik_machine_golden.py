"""Golden transcripts of the Sinumerik machine side (tests/data/golden/sinumerik/machine/*.mpf): the
canonical moves and the warnings, with the setup beside them (NAME.toml, else setup.toml: G54 at
(100, 50, -10), G505 at (10, 20, 0), axes A B rotary and W linear, M20/M70, T2 named "DRILL 8.5").
Regenerate with CUTSIM_UPDATE_GOLDEN=1 after checking the diff. Checked by hand:

- units: G70 X1 Y2 -> (25.4, 50.8) with F100 still mm/min (G70 leaves the feed alone); G91 X1 adds
  25.4; the G2 from (2, 2) inch about (2, 1) ends at (3, 1) inch = (76.2, 25.4); G700 F10 ->
  254 mm/min, G95 F0.01 -> 0.254 mm/rev; G710 F500 stays 500.
- settable: G54 X0 Y0 Z5 -> (100, 50, -5); G53 G0 Z100 is machine Z100 for its block only (X20
  afterwards is 120 again in G54); G505 X0 Y0 -> (10, 20); G55 has no offset (0, one warning);
  G500 X1 Y1 -> (1, 1).
- frames: ROT Z90: X10 -> (0, 10); TRANS X100 Y50 (clears the rotation): X10 -> (110, 50); AROT
  Z90: X10 -> (100, 60); ATRANS X5 moves along the turned X: X0 Y0 -> (100, 55); SCALE 2: X10 Y5
  -> (20, 10) and the CR=5 arc becomes radius 10 about (30, 10); ASCALE 0.5 gives scale 1 again;
  MIRROR X0: X10 -> -10, the G2 becomes CCW about (-10, 10), the G3 CW about (0, 0); AMIRROR Y0
  on top: X10 Y10 -> (-10, -10); TRANS alone: (10, 10).
- axes-tools: A, B and W move (one warning each, no motion of their own); M20 passes (declared);
  COMPOF, CYCLE832, CYCLE800 with zeros, G64 warn once; T="DRILL 8.5" M6 is T2; S2=/M2=3 address
  spindle 2 (a warning, and M2=3 is no program end); after T0 M6 (TOOL none) the G0 still runs, in G54:
  (0, 0, 100) -> (100, 50, 90).
- cycle-frame: POCKET2 of radius 8 with a 10 mm tool about (0, 0) runs its radius-3 circle; under
  TRANS X50 Y60 and AROT Z90 its start (0, -3) becomes (53, 60) and the circle runs about (50, 60),
  still counter-clockwise.
- frame-slot: see frame-slot.toml (the same mapping checked on the solid in test_sinumerik_machine).
"""
from __future__ import annotations

import os
from pathlib import Path

import pytest

from cutsim import interp_config, load_setup
from cutsim.interp import interpret
from cutsim.interp.canon import transcript

HERE = Path(__file__).resolve().parents[2] / "data" / "golden" / "sinumerik" / "machine"
PROGRAMS = sorted(HERE.glob("*.mpf"))


def run(prog: Path) -> str:
    toml = prog.with_suffix(".toml")
    setup = load_setup(str(toml if toml.exists() else HERE / "setup.toml"))
    cfg = interp_config(setup, setup.machine.start)
    p = interpret(str(prog.name), prog.read_text(), cfg)
    return transcript(p) + "".join(f"WARN {src.line}: {msg}\n" for src, msg in p.warnings)


@pytest.mark.parametrize("prog", PROGRAMS, ids=[p.stem for p in PROGRAMS])
def test_machine_golden(prog):
    out = run(prog)
    golden = prog.with_suffix(".txt")
    if os.environ.get("CUTSIM_UPDATE_GOLDEN"):
        golden.write_text(out)
    assert out == golden.read_text()
