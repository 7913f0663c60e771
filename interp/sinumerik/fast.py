"""The happy path of the Sinumerik block reader (interp/sinumerik/reader.py, ``scan_line``): a line
made only of an optional block number ``N<digits>`` and plain address words ``<letter><number>``
(``N10 G1 X20.5 Z-1 F100``), with an optional ``;`` comment, is split by one regular expression
into exactly the Line (with its ``Word(col, address, Num(value))`` statements) ``scan_line``
builds. Every other line gives None and goes the long way, which builds the Line or names the
error. tests/interp/core/test_fast_readers.py checks, line by line, that the two agree.

Conservative on purpose: only blanks and tabs between words, no blank between a letter and its
number, nothing but the ASCII letters of plain addresses (G M X Y Z I J K F S T D L P A B C U V W
R Q), signs, digits and points before the comment; no ``=``, ``(``, ``$``, ``"``, ``:``, ``/``,
``%``, no exponent; at most 12 digits on either side of the point (the long way's digit limit is
20); the block (its comment not counted) no longer than the long way's limit.

``plain_evaluate`` is Sinumerik.read_words for a block of constant G0/G1 X Y Z F words, without
the per-word hooks (tests/interp/core/test_fast_readers.py runs every Sinumerik program both ways).
Hooks: reader.split_units(..., fast=read_plain) and the first lines of Sinumerik.read_words.

``plain_block`` runs such a block without core.Interpreter.execute and Sinumerik's hooks on it (ISO
cycles, machine settings and move, MCALL, compensation) when it can tell that none of them
applies; hook: the first lines of Sinumerik.block. Same test, with it on and off.
"""
from __future__ import annotations

import dataclasses

from .syntax import COORD_LIMIT, MAX_BLOCK_CHARS, RANGES, Line, Num, Word
from ..core.fast import plain_patterns
from ..core.frames import ZERO

_LETTERS = "GMXYZIJKFSTDLPABCUVWRQ"
PLAIN_LINE, PLAIN_WORD = plain_patterns(_LETTERS, 12, r"[Nn]([0-9]{1,12})(?![0-9.])", r"(?s:;.*)?")
_UPPER = {c: c.upper() for c in _LETTERS + _LETTERS.lower()}


def _fields(cls) -> dict | None:
    """The fields of the dataclass ``cls`` with their defaults (MISSING for the required ones); None
    when a field has a default factory."""
    out = {}
    for f in dataclasses.fields(cls):
        if f.default_factory is not dataclasses.MISSING:
            return None
        out[f.name] = f.default
    return out


# Building Word and Num through their frozen ``__init__`` is a Python call per object; setting
# their fields with object.__setattr__ in the order of their declaration, as that ``__init__``
# does, gives the same objects (equal, hashable, the same compact instance layout) in less time.
# Only while the fields are those below (else the constructors are used).
_FAST = (_fields(Word) == {"col": dataclasses.MISSING, "address": dataclasses.MISSING,
                           "value": dataclasses.MISSING, "mode": None, "ext": None, "axis": None}
         and _fields(Num) == {"value": dataclasses.MISSING})


def read_plain(program: str, lineno: int, text: str) -> Line | None:
    """``reader.scan_line(program, lineno, text)`` for a plain line (blank and comment-only
    lines included); None for any other line."""
    m = PLAIN_LINE.fullmatch(text)
    if m is None or m.end(2) > MAX_BLOCK_CHARS:
        return None
    number, rest = m.groups()
    ln = Line(lineno, text, "", "" if number is None else "N" + str(int(number)))
    if rest:
        stmts = ln.stmts
        col = m.start(2) + 1
        upper = _UPPER
        if not _FAST:
            for letter, raw, gap in PLAIN_WORD.findall(rest):
                stmts.append(Word(col, upper[letter], Num(float(raw))))
                col += 1 + len(raw) + len(gap)
            return ln
        new = object.__new__
        put = object.__setattr__
        for letter, raw, gap in PLAIN_WORD.findall(rest):
            n = new(Num)
            put(n, "value", float(raw))
            w = new(Word)
            put(w, "col", col)
            put(w, "address", upper[letter])
            put(w, "value", n)
            put(w, "mode", None)
            put(w, "ext", None)
            put(w, "axis", None)
            stmts.append(w)
            col += 1 + len(raw) + len(gap)
    return ln


# -- evaluating a plain block ----------------------------------------------------------------------
_PLAIN_ADDRESSES = frozenset("XYZF")


def plain_evaluate(m, ln: Line, value) -> tuple[dict, list] | None:
    """``Sinumerik.read_words`` for a block of plain constant words only (G0/G1, X, Y, Z, F, each
    axis once, every value a finite constant within its address's range, no AC/IC, no extension,
    no address that is a variable of the running level or an extra axis of the setup): the same
    words (by address, ``value`` the interpreter's Value class, handed in: interp/sinumerik/
    interpreter.py imports this module) and G codes ((code, column) pairs), read without the
    per-word hooks (which do nothing to these words). None (nothing done) for any other block,
    which then goes the long way and raises its errors there."""
    words = {}
    gs = []
    scope = m.vars
    axes = m.cfg.axes
    for st in ln.stmts:
        if st.__class__ is not Word or st.mode is not None or st.ext is not None or st.axis is not None:
            return None
        node = st.value
        a = st.address
        if node.__class__ is not Num or a in scope or a in axes:
            return None
        v = node.value
        if a == "G":
            if v != 0.0 and v != 1.0:
                return None
            gs.append((int(v), st.col))
        elif a in _PLAIN_ADDRESSES and a not in words:
            lo, hi, _ = RANGES[a]
            if not lo <= v <= hi:  # NaN and inf too: the long way's error
                return None
            words[a] = value(v, None, st.col)
        else:
            return None
    return words, gs


# -- running a plain block -------------------------------------------------------------------------
def plain_block(m, ln: Line, src) -> bool:
    """``Sinumerik.block(ln, ...)`` for a block of plain constant G0/G1 X Y Z F words (as
    ``plain_evaluate`` takes them) when nothing else can apply: no ISO drilling cycle (m.drill.iso), no
    modal call (MCALL), radius compensation off, no chamfer or rounding waiting or modal (RNDM), the machine state (interp/sinumerik/machine.py)
    without inch units, programmable frame, work offset, pending warnings or deferred cycles; one
    motion code (or none) and G0/G1 active; F > 0; the end point within
    COORD_LIMIT. Then each hook of the long way does nothing but what is done here: clear the
    block's G53 suppression and arc flip, make F and the motion modal, emit the Rapid or Feed
    (through m.rapid / m.linear). False (nothing done) otherwise: the block goes the long way,
    which raises its errors there."""
    if m.comp_buf is not None or m.drill.iso is not None or m.drill.mcall is not None:
        return False
    cs = m.corners
    if (cs.hold is not None or cs.modal_r > 0.0):
        return False
    ms = m.machine
    if ms.pending or ms.deferred:
        return False
    modal = m.machine_modal
    if modal.inch or modal.inch_feed or modal.offset != ZERO or not modal.frame.identity():
        return False
    # the words as plain_evaluate takes them, read in place (no Block and Value objects built)
    scope = m.vars
    axes = m.cfg.axes
    motion = None
    vals = {}
    for st in ln.stmts:
        if st.__class__ is not Word or st.mode is not None or st.ext is not None or st.axis is not None:
            return False
        node = st.value
        a = st.address
        if node.__class__ is not Num or a in scope or a in axes:
            return False
        v = node.value
        if a == "G":
            if v != 0.0 and v != 1.0:
                return False
            if motion is not None and v != motion:
                return False  # G0 G1 in one block: the long way's error
            motion = v
        elif a in _PLAIN_ADDRESSES and a not in vals:
            lo, hi, _ = RANGES[a]
            if not lo <= v <= hi:  # NaN and inf too
                return False
            vals[a] = v
        else:
            return False
    if motion is not None:
        motion = int(motion)
    mode = m.motion if motion is None else motion
    if mode != 0 and mode != 1:
        return False  # G2/G3 or another motion active
    feed = vals.get("F")
    if feed is not None and feed <= 0:
        return False  # the long way's "feed F must be positive"
    end = None
    if "X" in vals or "Y" in vals or "Z" in vals:
        pos = m.pos
        absolute = m.absolute
        if "X" in vals and modal.diam != "DIAMOF" and (modal.diam == "DIAMON" or absolute and modal.diam == "DIAM90"):
            vals["X"] *= 0.5  # a diameter (lathe.x_words): the position is kept as a radius
        end = [pos[0], pos[1], pos[2]]
        for i, a in enumerate("XYZ"):
            v = vals.get(a)
            if v is not None:
                if not absolute:
                    v = pos[i] + v
                if not -COORD_LIMIT <= v <= COORD_LIMIT:
                    return False  # the long way's range error
                end[i] = v
    ms.suppress = False
    ms.arc_flip = False
    if feed is not None:
        m.feed = feed
    if motion is not None:
        m.motion = motion
    if end is not None:
        (m.rapid if mode == 0 else m.linear)(src, (end[0], end[1], end[2]))
    return True
