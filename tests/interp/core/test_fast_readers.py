"""The plain-line readers (interp/isg/fast.py, interp/sinumerik/fast.py) are shortcuts of the full
line readers (interp/isg/reader.py scan, sinumerik_reader.scan_line): for every line they give either None
(the line goes the long way) or exactly the object the full reader builds, field by field. A
line the full reader refuses (an error) must give None.

Checked on every line of every program under tests/, examples/ and ../shared/examples (both
readers on every program, whatever its dialect: the property holds for any line), on lines made
of random pieces (hypothesis, derandomized) and on the lines of the benchmark's programs.
"""
from __future__ import annotations

import sys
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cutsim.interp.sinumerik import fast as sinumerik_fast
from cutsim.interp.sinumerik import reader as sinumerik_reader, syntax as sinumerik_syntax
from cutsim.interp.isg import fast as isg_fast, program as isg_program, reader as isg_scan
from cutsim.interp.errors import CutsimError
from cutsim.interp.core.lexer import split_lines

ROOT = Path(__file__).resolve().parents[3]
DIRS = [ROOT / "tests", ROOT / "examples", ROOT.parent / "shared" / "examples"]


def program_lines() -> list[str]:
    """Every distinct line of every program file (.nc, .mpf, .spf) in DIRS."""
    seen: dict[str, None] = {}
    for d in DIRS:
        if not d.is_dir():
            continue
        for p in sorted(d.rglob("*")):
            if p.suffix.lower() in (".nc", ".mpf", ".spf") and p.is_file():
                for line in split_lines(p.read_text(encoding="utf-8", errors="replace")):
                    seen.setdefault(line, None)
    return list(seen)


LINES = program_lines()


def full_isg(line: str):
    try:
        return isg_scan.scan("p.nc", 7, line)
    except CutsimError as e:
        return ("error", str(e))


def full_sinumerik(line: str):
    try:
        return sinumerik_reader.scan_line("p.mpf", 7, line)
    except CutsimError as e:
        return ("error", str(e))


def check_isg(line: str) -> bool:
    """The ISG property for one line; True when the shortcut took it."""
    fast = isg_fast.read_plain("p.nc", 7, line)
    if fast is None:
        return False
    full = full_isg(line)
    assert isinstance(full, isg_scan.IsgBlock), (line, full)
    assert fast == full, line
    assert [type(w) for w in fast.words] == [type(w) for w in full.words]
    assert [type(w.value) for w in fast.words] == [type(w.value) for w in full.words]
    # what isg_program.parse does before it scans a line leaves a plain line as it is
    assert isg_program.expand_macros("p.nc", 7, line, {}) == line
    assert isg_scan.MACRO_DEF.match(line) is None
    assert not line.lstrip().startswith("%") and "\\" not in line.split(";", 1)[0]
    return True


def check_sinumerik(line: str) -> bool:
    fast = sinumerik_fast.read_plain("p.mpf", 7, line)
    if fast is None:
        return False
    full = full_sinumerik(line)
    assert isinstance(full, sinumerik_syntax.Line), (line, full)
    assert fast == full, line
    assert [type(s) for s in fast.stmts] == [type(s) for s in full.stmts]
    assert [type(s.value.value) for s in fast.stmts] == [type(s.value.value) for s in full.stmts]
    return True


def test_there_are_program_lines():
    assert len(LINES) > 1000


def test_every_program_line_isg():
    taken = sum(check_isg(line) for line in LINES)
    assert taken > 200  # the shortcut is used at all


def test_every_program_line_sinumerik():
    taken = sum(check_sinumerik(line) for line in LINES)
    assert taken > 200


PIECES = ["N", "n", "N10", "G", "g", "G01", "G1", "G4", "G04", "M", "M30", "X", "x", "Y", "Z", "I", "J", "K", "F",
          "S", "S.", "OFFSET", "T", "D", "L", "LL", "H", "A", "B", "C", "U", "V", "V.", "W", "R", "P", "Q", "E", "@",
          "0", "1", "01", "7.", ".5", "-", "+", "\u2212", ".", "99999", "99999.9999", "100000", "99999999",
          "123456789", "1234567890123", "1e3", "EX3", " ", "  ", "\t", "\f", "\v", ";", "; c", '"', '"M"', "(", ")",
          "[", "]", "=", ":", "/", "#", "$", "%", "\\", "\x1a", "\x00", "\uff11", "\u0661", "\u00e4", "\r", "AC(",
          "IC(", "CR=", "1=", "DEF", "IF", "GOTOF", "MSG", "SIN(", "R1", "R1=", "P1", "P[1]"]


@settings(max_examples=3000, deadline=None, derandomize=True)
@given(st.lists(st.sampled_from(PIECES), max_size=16))
def test_random_lines_isg(pieces):
    check_isg("".join(pieces))


@settings(max_examples=3000, deadline=None, derandomize=True)
@given(st.lists(st.sampled_from(PIECES), max_size=16))
def test_random_lines_sinumerik(pieces):
    check_sinumerik("".join(pieces))


WORDS = ["G0", "G1", "G01", "G2", "G03", "G4", "G17", "G90", "G91", "G33", "M3", "M30", "X10", "X-5.5", "X20.", "Z-3",
         "Z.5", "Y2", "I5", "K-2", "F0.1", "F100", "S500", "T1", "D1", "A90", "C-45", "U1", "W2", "R5", "Q2", "L5",
         "H3", "P2", "x1", "z-.25", "X99999.9999", "X100000", "F-1", "N5"]


@settings(max_examples=2000, deadline=None, derandomize=True)
@given(st.booleans(), st.lists(st.sampled_from(WORDS), max_size=7), st.sampled_from(["", " ", "\t"]),
       st.sampled_from(["", " ;c", ';"x" # (y)', "; \u00e4"]))
def test_random_blocks(numbered, words, gap, comment):
    """Blocks shaped like real ones: the shortcut takes most of them; both properties hold."""
    line = ("N10 " if numbered else "") + gap.join(words) + comment
    check_isg(line)
    check_sinumerik(line)


def test_plain_blocks_are_taken():
    """The lines the benchmark is made of go the short way (else it measures nothing)."""
    sys.path.insert(0, str(ROOT / "bench"))
    try:
        import bench_interp
    finally:
        sys.path.pop(0)
    for case in ("isg-lathe", "isg-mill", "sinumerik-mill", "sinumerik-lathe"):
        lines = bench_interp.program(case, 300).splitlines()
        check = check_isg if case.startswith("isg") else check_sinumerik
        taken = [check(line) for line in lines if not line.startswith("%")]
        assert all(taken), case


@pytest.mark.parametrize("line, words", [
    ("N10 G01 X20.5 Z-1 F100", [("G", 1.0, "01", 5), ("X", 20.5, "20.5", 9), ("Z", -1.0, "-1", 15), ("F", 100.0, "100", 19)]),
    ("\tg1x.5 ; comment", [("G", 1.0, "1", 2), ("X", 0.5, ".5", 4)]),
])
def test_isg_words_by_hand(line, words):
    b = isg_fast.read_plain("p.nc", 3, line)
    assert [(w.letter, w.value, w.raw, w.col) for w in b.words] == words
    assert b.line == 3 and b.items == [("w", w) for w in b.words]


@pytest.mark.parametrize("line", ["N10 X1 X2", "X100000", "L5", "N10: X1", "X 1", "X1.2.3", "G04 3.0", "/X1", "X1 N5",
                                  "P1=2", "V.L.A=1", "H5", "X1 (c)", ""])
def test_isg_not_plain(line):
    assert isg_fast.read_plain("p.nc", 1, line) is None


@pytest.mark.parametrize("line", ["X=5", "M3=1", "X1 N5", "X 1", "X1.2.3", "/X1", "R1=2", "X1EX3", "N1: X1",
                                  "X" + "1" * 13, "H5", "%_N_A_MPF", "X1\f"])
def test_sinumerik_not_plain(line):
    assert sinumerik_fast.read_plain("p.mpf", 1, line) is None


def test_sinumerik_words_by_hand():
    ln = sinumerik_fast.read_plain("p.mpf", 4, "N0010 G1 x-2.5 ; \u00e4 \"q\"")
    assert (ln.line, ln.text, ln.label, ln.nlabel) == (4, "N0010 G1 x-2.5 ; \u00e4 \"q\"", "", "N10")
    assert [(s.col, s.address, s.value.value) for s in ln.stmts] == [(7, "G", 1.0), (10, "X", -2.5)]


def test_sinumerik_both_ways_of_building_words(monkeypatch):
    """The reader fills the frozen Word/Num instances directly (sinumerik_fast._FAST); through
    their constructors it builds the same objects."""
    assert sinumerik_fast._FAST  # else the fast way is not what the other tests check
    lines = [line for line in LINES if sinumerik_fast.read_plain("p.mpf", 7, line) is not None]
    direct = [sinumerik_fast.read_plain("p.mpf", 7, line) for line in lines]
    monkeypatch.setattr(sinumerik_fast, "_FAST", False)
    built = [sinumerik_fast.read_plain("p.mpf", 7, line) for line in lines]
    assert direct == built and len(lines) > 200
    assert [hash(s) for ln in direct for s in ln.stmts] == [hash(s) for ln in built for s in ln.stmts]


def test_sinumerik_fast_words_take_no_more_memory(monkeypatch):
    """Words built the fast way keep the compact instance layout of the constructed ones (filling
    their __dict__ directly would double their size)."""
    import tracemalloc

    line = "N10 G1 X12.5 Y-3 Z-1.25 F100"

    def size() -> int:
        tracemalloc.start()
        keep = [sinumerik_fast.read_plain("p.mpf", 1, line) for _ in range(2000)]
        used = tracemalloc.get_traced_memory()[0]
        tracemalloc.stop()
        assert len(keep) == 2000
        return used
    fast = size()
    monkeypatch.setattr(sinumerik_fast, "_FAST", False)
    built = size()
    assert fast <= built * 1.02


# -- the ISG plain block (Isg.plain_block): whole programs run alike with and without it -------
from cutsim.interp import canon, isg  # noqa: E402
from cutsim.interp.core.modal import InterpConfig  # noqa: E402

ISG_CFGS = {
    "lathe": InterpConfig("isg", "lathe", True, (40.0, 0.0, 5.0), parameters={1: 2.5}, max_blocks=3000,
                          work_offsets={"G54": (1.0, 0.0, -2.0)}),
    "mill": InterpConfig("isg", "mill", False, (0.0, 0.0, 20.0), max_blocks=3000, tool_radii={1: 3.0, 2: 1.0},
                         axes={"A": "rotary", "U": "linear"}, work_offsets={"G55": (10.0, -5.0, 0.5)}),
}


def isg_outcome(name: str, text: str, cfg: InterpConfig, short: bool):
    """Run the program with the plain-block path (``short``: every block offered to
    Isg.plain_block first, as the hook in Isg.block does) or without it."""
    mp = pytest.MonkeyPatch()
    original = isg.Isg.block
    if short:
        def block(self, b, fr):
            src = canon.Src(self.name, b.line, 1, b.label, fr.calls)
            if self.plain_block(b, src, fr):
                return False
            return original(self, b, fr)
        mp.setattr(isg.Isg, "block", block)
    else:
        mp.setattr(isg.Isg, "plain_block", lambda *a: False)
    try:
        p = isg.interpret(name, text, cfg)
    except CutsimError as e:
        return "error", str(e)
    finally:
        mp.undo()
    return canon.transcript(p), p.warnings, p.blocks, p.final_position


def isg_programs() -> list[Path]:
    out = []
    for d in DIRS:
        if d.is_dir():
            out += [p for p in sorted(d.rglob("*.nc")) if "isg" in str(p.relative_to(d)).lower()]
    return out


def test_there_are_isg_programs():
    assert len(isg_programs()) >= 30


@pytest.mark.parametrize("kind", ["lathe", "mill"])
@pytest.mark.parametrize("path", isg_programs(), ids=lambda p: f"{p.parent.name}/{p.name}")
def test_isg_programs_run_alike(path, kind):
    text = path.read_text(encoding="utf-8", errors="replace")
    cfg = ISG_CFGS[kind]
    assert isg_outcome(str(path), text, cfg, True) == isg_outcome(str(path), text, cfg, False)


ISG_WORDS = ["G0", "G00", "G1", "G01", "G1.0", "G2", "G03", "G33", "G90", "G91", "G54", "G55", "G53", "G92", "G51",
             "G52", "G41", "G42", "G40", "G17", "G18", "G4", "G95", "X10", "X-5.5", "X20.", "Z-3", "Z.5", "Y2", "I5",
             "K-2", "K1.5", "F0.1", "F100", "F0", "F-1", "S500", "M3", "M5", "T1", "D1", "D0", "A90", "U1", "B5",
             "R5", "X99999.9999", "X100000", "Z-99999", "M30", "M17", "H2", "P1=3", "X=P1", "#MCS ON", "#MCS OFF",
             "#CS ON[1,2,3,0,0,0]", "#CS OFF", "N5", "(c)", "; c"]


# mostly words a plain block may hold or nearly (so that most programs run far), the rest seldom
ISG_MIX = ISG_WORDS + ["G1", "G0", "G01", "X1", "X12.5", "Z-1", "Z-4", "Y-2.25", "F50", "F0.2", "S300", "M3", "T1",
                       "A10", "I1", "K-1", "G90", "G91"] * 8


@settings(max_examples=800, deadline=None, derandomize=True)
@given(st.lists(st.lists(st.sampled_from(ISG_MIX), max_size=5), max_size=14), st.sampled_from(["lathe", "mill"]),
       st.booleans())
def test_random_isg_programs_run_alike(lines, kind, header):
    body = "\n".join(f"N{k + 1} " + " ".join(ws) for k, ws in enumerate(lines))
    text = ("%p\n" if header else "") + body + "\nM30\n"
    cfg = ISG_CFGS[kind]
    assert isg_outcome("p.nc", text, cfg, True) == isg_outcome("p.nc", text, cfg, False)


def test_plain_blocks_take_the_short_way(monkeypatch):
    """The benchmark's blocks are run by plain_block (else the speed-up measures nothing)."""
    sys.path.insert(0, str(ROOT / "bench"))
    try:
        import bench_interp
    finally:
        sys.path.pop(0)
    taken, missed = set(), set()
    real = isg.Isg.plain_block

    def spy(m, b, *a):
        ok = real(m, b, *a)
        (taken if ok else missed).add(b.line)
        return ok
    monkeypatch.setattr(isg.Isg, "plain_block", spy)
    text = bench_interp.program("isg-mill", 50)
    original = isg.Isg.block

    def block(self, b, fr):
        src = canon.Src(self.name, b.line, 1, b.label, fr.calls)
        return False if self.plain_block(b, src, fr) else original(self, b, fr)
    monkeypatch.setattr(isg.Isg, "block", block)
    isg.interpret("p.nc", text, ISG_CFGS["mill"])
    assert taken == set(range(2, 52)) and missed == {52}  # the blocks (after %bench); M30 the long way


# -- the Sinumerik plain block (sinumerik_fast.plain_evaluate, plain_block): programs run alike -----
from cutsim.interp import sinumerik  # noqa: E402

SIN_CFGS = {
    "mill": InterpConfig("sinumerik", "mill", False, (0.0, 0.0, 50.0), parameters={1: 2.5}, max_blocks=3000,
                         tool_radii={1: 3.0, 2: 1.0}, axes={"A": "rotary"}, work_offsets={"G54": (10.0, 5.0, 0.0)}),
    "lathe": InterpConfig("sinumerik", "lathe", True, (40.0, 0.0, 5.0), max_blocks=3000),
}
# which shortcuts are on: both (as shipped), plain_evaluate alone (Sinumerik.block's hook off), none
SIN_MODES = ("both", "evaluate", "none")


def sin_outcome(name: str, text: str, cfg: InterpConfig, mode: str):
    """Run with the hooks in Sinumerik.block (plain_block) and Sinumerik.evaluate (plain_evaluate)
    as shipped (``both``), with plain_block off (``evaluate``) or with both off (``none``); the
    hooks call them through the module, so switching them off here takes the long way."""
    mp = pytest.MonkeyPatch()
    if mode != "both":
        mp.setattr(sinumerik_fast, "plain_block", lambda *a: False)
    if mode == "none":
        mp.setattr(sinumerik_fast, "plain_evaluate", lambda *a: None)
    try:
        p = sinumerik.interpret(name, text, cfg)
    except CutsimError as e:
        return "error", str(e)
    finally:
        mp.undo()
    return canon.transcript(p), p.warnings, p.blocks, p.final_position


def sin_alike(name: str, text: str, cfg: InterpConfig) -> None:
    both, evaluate, none = (sin_outcome(name, text, cfg, mode) for mode in SIN_MODES)
    assert both == none
    assert evaluate == none


def sin_programs() -> list[Path]:
    out = []
    for d in DIRS:
        if d.is_dir():
            out += sorted(p for p in d.rglob("*") if p.suffix.lower() == ".mpf")
    return out


def test_there_are_sinumerik_programs():
    assert len(sin_programs()) >= 50


@pytest.mark.parametrize("kind", ["mill", "lathe"])
@pytest.mark.parametrize("path", sin_programs(), ids=lambda p: f"{p.parent.name}/{p.name}")
def test_sinumerik_programs_run_alike(path, kind):
    text = path.read_text(encoding="utf-8", errors="replace")
    sin_alike(str(path), text, SIN_CFGS[kind])


SIN_WORDS = ["G0", "G1", "G01", "G1.0", "G2", "G3", "G4", "G90", "G91", "G54", "G500", "G53", "G70", "G71", "G700",
             "G17", "G18", "G41", "G40", "G64", "G95", "X10", "X-5.5", "Z-3", "Z.5", "Y2", "I5", "K-2", "F0.1", "F100",
             "F0", "F-1", "S500", "M3", "M5", "M6", "T1", "T0", "D1", "A90", "B5", "U1", "X99999.9999", "X100000",
             "M30", "M17", "R1=3", "X=R1", "X=IC(2)", "X1 X2", "TRANS X5", "ROT Z30", "SCALE X2", "MIRROR X0",
             "TRANS", "AROT Z10", "SUPA", "CR=5", "DEF REAL X", "N5", "; c", "MCALL CYCLE81(10,0,2,-5)", "MCALL",
             "G81", "G83", "G80", "R2", "Q1", "G0 G1", "G42", "G2", "X-99999.9999", "G53 X0", "G291", "G64"]
SIN_MIX = SIN_WORDS + ["G1", "G0", "X1", "X12.5", "Z-1", "Z-4", "Y-2.25", "F50", "F0.2", "S300", "M3", "T1", "A10",
                       "G90", "G91"] * 8


@settings(max_examples=800, deadline=None, derandomize=True)
@given(st.lists(st.lists(st.sampled_from(SIN_MIX), max_size=5), max_size=14), st.sampled_from(["mill", "lathe"]))
def test_random_sinumerik_programs_run_alike(lines, kind):
    text = "\n".join(f"N{k + 1} " + " ".join(ws) for k, ws in enumerate(lines)) + "\nM30\n"
    sin_alike("p.mpf", text, SIN_CFGS[kind])


def bench_program(case: str, n: int) -> str:
    sys.path.insert(0, str(ROOT / "bench"))
    try:
        import bench_interp
    finally:
        sys.path.pop(0)
    return bench_interp.program(case, n)


def test_sinumerik_plain_blocks_take_the_short_way(monkeypatch):
    """The benchmark's blocks are evaluated by plain_evaluate (with plain_block off: else it would
    take them first) ..."""
    taken, missed = set(), set()
    real = sinumerik_fast.plain_evaluate

    def spy(m, ln, *a):
        (missed if real(m, ln, *a) is None else taken).add(ln.line)
    monkeypatch.setattr(sinumerik_fast, "plain_evaluate", spy)
    sin_outcome("p.mpf", bench_program("sinumerik-mill", 50), SIN_CFGS["mill"], "evaluate")
    assert taken == set(range(1, 51)) and missed == {51}  # the blocks; M30 goes the long way


@pytest.mark.parametrize("case,kind", [("sinumerik-mill", "mill"), ("sinumerik-lathe", "lathe")])
def test_sinumerik_plain_blocks_run_the_short_way(monkeypatch, case, kind):
    """... and run by plain_block, through its hook in Sinumerik.block (else the speed-up measures
    nothing); M30 goes the long way."""
    taken, missed = set(), set()
    real = sinumerik_fast.plain_block

    def spy(m, ln, *a):
        ok = real(m, ln, *a)
        (taken if ok else missed).add(ln.line)
        return ok
    monkeypatch.setattr(sinumerik_fast, "plain_block", spy)
    out = sin_outcome("p.mpf", bench_program(case, 50), SIN_CFGS[kind], "both")
    assert out[0] != "error" and out[2] == 51
    assert taken == set(range(1, 51)) and missed == {51}


def test_plain_block_declines_what_it_cannot_prove():
    """With an ISO cycle, a modal call, a frame, an offset, inch units, compensation or an arc mode
    active, the last block (X1 ..) goes the long way (each program also runs alike: the tests
    above); with no tool in the spindle (T0 M6) it is still plain: the long way does nothing else."""
    ok = "G1 X1 F10"
    cases = [ok, "G0 X1", "T0 M6\n" + ok, "G81 Z-2 R1\nX1", "MCALL CYCLE81(10,0,2,-5)\n" + ok, "TRANS X5\n" + ok,
             "G54\n" + ok, "G70\n" + ok, "T1 D1 M6\nG41 G1 X0 Y0 F10\n" + ok, "G2 X0 Y0 I1 F10\nX1",
             "G0 G1 X1 F10", "G1 X1 F0", "G1 X1 A5 F10", "G1 X1 I2 F10", "G1 X=IC(1) F10", "G91 G1 X99999 F1\nX1"]
    real = sinumerik_fast.plain_block
    for k, text in enumerate(cases):
        last = text.count("\n") + 1
        seen = []

        def spy(m, ln, *a):
            took = real(m, ln, *a)
            if ln.line == last:
                seen.append(took)
            return took
        mp = pytest.MonkeyPatch()
        mp.setattr(sinumerik_fast, "plain_block", spy)
        try:
            sin_outcome("p.mpf", text + "\nM30\n", SIN_CFGS["mill"], "both")
        finally:
            mp.undo()
        assert seen == ([True] if k < 3 else [False]), text


@pytest.mark.parametrize("line", ["G01" * 100000 + "@", "G01 " * 100000 + "@", "X" + "1" * 30000, "N" + "1" * 30000,
                                  "X1" + ".5" * 30000, " " * 100000 + "@", "X1.1" * 50000 + "."])
def test_long_lines_that_are_not_plain(line):
    """Lines the shortcut can't take fail in linear time (the regular expressions do not backtrack
    over their words: each number must end where its digits end); here they just give None."""
    assert isg_fast.read_plain("p.nc", 1, line) is None
    assert sinumerik_fast.read_plain("p.mpf", 1, line) is None
