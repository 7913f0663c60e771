"""M70-M73 (the modal state saved and restored) and G10 L10/L11 (tool lengths from the position),
against values worked out by hand from docs/dialects/rs274ngc.md; test_rs274ngc_oracle.py compares
them with rs274 (tests/data/programs/rs274ngc/context.ngc and the random programs)."""
from __future__ import annotations

import pytest

from cutsim.interp import interpret
from cutsim.interp.canon import Feed, Rapid
from cutsim.interp.core.modal import InterpConfig
from cutsim.interp.errors import CutsimError


def moves(text: str, tools: str = ""):
    cfg = InterpConfig(dialect="rs274ngc", tool_table=tools)
    prog = interpret("t.ngc", "G21 G17 G90 F100\n" + text + "\nM2\n", cfg)
    return [r for r in prog.records if isinstance(r, (Rapid, Feed))]


def test_m72_restores_units_distance_and_feed():
    ms = moves("G0 X0 Y0 Z0\nM70\nG20 G91\nF5\nG1 X1\nM72\nG1 X2")
    # in G20 G91: 1 in = 25.4 mm from X0 at 5 in/min; after M72 absolute X2 mm at F100 mm/min again
    assert (ms[1].end[0], ms[1].feed) == pytest.approx((25.4, 127.0))
    assert (ms[2].end[0], ms[2].feed) == pytest.approx((2.0, 100.0))


def test_m73_restores_at_the_return_of_its_subroutine():
    sub = "o<s> sub\nM73\nG91 G20\nG1 X1\no<s> endsub\n"
    ms = moves(sub + "G0 X0 Y0 Z0\no<s> call\nG1 X2")
    assert ms[-1].end[0] == pytest.approx(2.0)  # G90 G21 again: X2 mm, not 2 in further


def test_m72_without_a_saved_state_at_its_level_is_refused():
    with pytest.raises(CutsimError, match="no M70 or M73"):
        moves("M70\nM71\nM72")


def test_g10_l10_sets_the_length_that_makes_the_position_read_the_given_value(tmp_path):
    # tool 1 of 12.7 with G43: program Z10 puts the spindle at 22.7. G10 L10 P1 Z5: length 22.7 - 5 =
    # 17.7; after G43 again, G0 Z10 puts the tip (spindle - 12.7, the loaded length) at 10 + 17.7 - 12.7
    tbl = tmp_path / "t.tbl"
    tbl.write_text("T1 P1 Z12.7\n")
    ms = moves("T1 M6\nG43\nG0 X0 Y0 Z10\nG10 L10 P1 Z5\nG43\nG0 Z10", str(tbl))
    assert ms[-1].end[2] == pytest.approx(10 + 17.7 - 12.7)
    # L11 ignores the G55 offset (Z3 here) and counts in G59.3's (0): Z7 in G55 is the spindle at
    # 7 + 3 + 12.7 = 22.7, the length 22.7 - 4 = 18.7; G43, G0 Z7: the tip at 7 + 3 + 18.7 - 12.7
    ms = moves("T1 M6\nG43\nG10 L2 P2 Z3\nG55 G0 X0 Y0 Z7\nG10 L11 P1 Z4\nG43\nG0 Z7", str(tbl))
    assert ms[-1].end[2] == pytest.approx(7 + 3 + 18.7 - 12.7)
