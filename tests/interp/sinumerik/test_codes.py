"""The Sinumerik G and M tables (interp/sinumerik/codes.py) decide what the interpreter accepts:
every code in them is known, every other one is an error at its word; two codes of one of the
language's modal groups in a block conflict, codes of different groups do not; Code.words of the
motion codes decides which blocks may carry a circle's I/J/K/CR.
"""
from __future__ import annotations

import itertools

import pytest

from cutsim.interp import CutsimError, InterpConfig, interpret
from cutsim.interp.sinumerik.codes import G_CODES, LANGUAGE_GROUPS, M_CODES

CFG = InterpConfig("sinumerik", "mill", False, (0.0, 0.0, 50.0), tool_radii={1: 3.0}, m_functions=frozenset({77}))


def outcome(text: str) -> str:
    try:
        interpret("p.mpf", text, CFG)
    except CutsimError as e:
        return str(e)
    return "ok"


@pytest.mark.parametrize("code", sorted(G_CODES))
def test_every_table_g_code_is_known(code):
    assert "unknown G code" not in outcome(f"G{code}\nM30\n")


@pytest.mark.parametrize("code", [5, 8, 20, 21, 58, 59, 65, 100, 154, 504, 600, 646, 1000])
def test_codes_outside_the_table_are_refused_at_their_word(code):
    assert code not in G_CODES
    assert outcome(f"G1 X1 F100\nX2 G{code}\nM30\n") == f"p.mpf:2:4: error: unknown G code G{code}"


@pytest.mark.parametrize("code", sorted(M_CODES))
def test_every_table_m_code_is_known(code):
    assert "not known" not in outcome(f"T1 M{code}\nM30\n")


def test_m_codes_outside_the_table_need_the_setup():
    assert outcome("M77\nM30\n") == "ok"  # [machine] m_functions
    assert outcome("G0 X1 M78\nM30\n").startswith("p.mpf:1:7: error: M78 is not known to the simulator")


PAIRS = [(a, b) for g in sorted(LANGUAGE_GROUPS, key=lambda g: g.value) for a, b in itertools.combinations(sorted(c for c, r in G_CODES.items()
                                                                                  if r.group is g), 2)]


@pytest.mark.parametrize("a,b", PAIRS)
def test_two_codes_of_one_language_group_conflict(a, b):
    group = G_CODES[a].group
    name = group.value  # "motion", "plane", ...: the group as a user reads it
    assert outcome(f"G{a} G{b} X1\nM30\n") == \
        f"p.mpf:1:{len(str(a)) + 3}: error: G{b} conflicts with G{a} in the same block (both {name})"


def test_codes_of_different_groups_and_repeated_codes_do_not_conflict():
    assert outcome("G90 G17 G94 G1 G1 X1 F100 G64 G54 G97\nM30\n") == "ok"


@pytest.mark.parametrize("motion", [0, 1])
@pytest.mark.parametrize("address", ["I1", "J1", "K1", "CR=1"])
def test_circle_words_only_on_circles(motion, address):
    assert "I" not in G_CODES[motion].words and "CR" in G_CODES[2].words.split()
    letter = address.rstrip("=1")
    assert outcome(f"G{motion} X1 {address}\nM30\n") == \
        f"p.mpf:1:{len(str(motion)) + 6}: error: address {letter} has no meaning in a G{motion} block"
    assert outcome(f"G{motion} X1\nG2 X2 {address.replace('1', '0.5') if 'CR' in address else 'I0.5'}\nM30\n") == "ok"
