"""Coordinate systems, G92 and G52 (its offsets, as LinuxCNC 2.9 keeps them), G10, G28/G30 and tool length offsets, kept where LinuxCNC keeps them: in
the numbered parameters (mm). G54..G59.3 are systems 1..9 at #5221 + 20 * (n - 1) (X, Y, Z), the
active one in #5220; G92 at #5211-#5213 (#5210 = 1 while applied); G28 at #5161-#5163 and G30 at
#5181-#5183 (machine coordinates).
"""
from __future__ import annotations

from cutsim.interp.core import Group, Step
from cutsim.interp.core.lexer import Word

from . import exact

SYSTEMS = {54: 1, 55: 2, 56: 3, 57: 4, 58: 5, 59: 6, 59.1: 7, 59.2: 8, 59.3: 9}


def base(n: int) -> int:
    """The parameter of system ``n``'s X offset (1 = G54 ... 9 = G59.3)."""
    return 5221 + 20 * (n - 1)


def load(m) -> None:
    """The start state: the setup's [work_offsets] into the parameters (over the .var file's),
    the active system from #5220 (G54 if unset) and G92 from #5211-#5213 if #5210 is set."""
    num = m.params.numbered
    for name, vals in m.cfg.work_offsets.items():
        code = float(name[1:])
        if code in SYSTEMS:
            for i in range(3):
                num[base(SYSTEMS[code]) + i] = float(vals[i])
    m.coord = int(num.get(5220, 1.0)) if 1 <= num.get(5220, 1.0) <= 9 else 1
    m.g5x = [num.get(base(m.coord) + i, 0.0) for i in range(3)]
    if num.get(5210, 0.0) != 0.0:
        m.g92 = [num.get(5211 + i, 0.0) for i in range(3)]


def select(m, code: float) -> None:
    select_system(m, SYSTEMS[code])


def select_system(m, n: int) -> None:
    m.coord = n
    m.params.numbered[5220] = float(n)
    m.g5x = [m.params.numbered.get(base(n) + i, 0.0) for i in range(3)]


def tool_length(m, st: Step) -> None:
    """G43 [H], G43.1 X Z, G43.2 H / X Z, G49 (after M6 in the block, as LinuxCNC orders them)."""
    g = st.g.pop(Group.TOOL_LENGTH, None)
    if g is None:
        return
    code, line = round(g.value, 4), st.block.line
    if m.comp_side:
        raise m.error(line, g.col, f"G{g.raw}: cannot change the tool length offset with cutter radius compensation on "
                      "(G40 first)")
    words = st.words
    m.tlo_mode = code
    if code == 49:
        m.set_tlo([0.0, 0.0, 0.0])
        return
    if code in (43, 43.2) and "H" in words or code == 43:
        h = words.pop("H", None)
        number = m.tool_no if h is None else m.whole(line, h, "tool number H")
        if number not in m.tools and number != 0:
            m.warn(m.src(st), f"G43 H{number}: tool {number} has no entry in the tool table; length offset 0")
        entry = m.tools.get(number, {})
        vals = [entry.get("X", 0.0), 0.0, entry.get("Z", 0.0)]
        m.set_tlo(vals if code == 43 else [m.tlo[i] + vals[i] for i in range(3)])
        return
    if not any(a in words for a in "XZ"):
        raise m.error(line, g.col, f"G{g.raw} needs X or Z offsets")
    # G43.1 sets the offsets of the axes given, G43.2 adds to them; the others keep theirs (rs274 2.9)
    tlo = list(m.tlo)
    for i, a in ((0, "X"), (2, "Z")):
        if a in words:
            v = words.pop(a).value * m.scale
            tlo[i] = v if code == 43.1 else tlo[i] + v
    m.set_tlo(tlo)


COMP_REFUSED = {28: "cannot go home", 30: "cannot go home", 28.1: "cannot set a home position",
                30.1: "cannot set a home position", 92: "cannot set axis offsets"}


def nonmodal(m, st: Step, code: float, g: Word) -> None:
    if code in COMP_REFUSED and m.comp_side:
        raise m.error(st.block.line, g.col, f"G{g.raw}: {COMP_REFUSED[code]} with cutter radius compensation on "
                      "(G40 first)")
    if code in (92, 92.1, 92.2, 92.3):
        before = exact.before_g92(m)
        words = {i: st.words[a] for i, a in enumerate("XYZ") if a in st.words}
        g92(m, st, code, g)
        exact.g92(m, code, words, before)
        return
    if code == 10:
        g10(m, st, g)
    elif code in (28, 30):
        home(m, st, 5161 if code == 28 else 5181)
    elif code in (28.1, 30.1):
        first = 5161 if code == 28.1 else 5181
        for i in range(3):
            m.params.numbered[first + i] = m.base()[i] + m.tool_len[i]
    elif code == 52:  # LinuxCNC 2.9: the G92 offsets of the axes given set to their values (G90 or G91)
        for i, w in axis_words(st).items():
            m.g92[i] = w.value * m.unit(i)
        m.params.numbered[5210] = 1.0
        for i in range(3):
            m.params.numbered[5211 + i] = m.g92[i]
        exact.forget_g92(m)


def g92(m, st: Step, code: float, g: Word) -> None:
    if code == 92:
        set_g92(m, st, g)
    elif code in (92.1, 92.2):  # #5210 (G92 applied) 0 after both; G92.1 clears the stored offsets too
        m.g92 = [0.0, 0.0, 0.0]
        for i in range(5210, 5214 if code == 92.1 else 5211):
            m.params.numbered[i] = 0.0
    elif code == 92.3:  # the stored offsets applied again: #5210 1 (rs274 2.9, measured)
        m.g92 = [m.params.numbered.get(5211 + i, 0.0) for i in range(3)]
        m.params.numbered[5210] = 1.0


def axis_words(st: Step) -> dict[int, Word]:
    return {i: st.words.pop(a) for i, a in enumerate("XYZ") if a in st.words}


def home(m, st: Step, first: int) -> None:
    """G28/G30: through the point of the axis words (if any) to the stored machine position of
    those axes (all axes without words), both at rapid rate."""
    words = {i: w for i, w in ((i, st.words.get(a)) for i, a in enumerate("XYZ")) if w is not None}
    if words:
        mid, _ = m.goal(st)
        m.rapid(m.src(st), mid)
    end = m.base()
    for i in (words or range(3)):
        end[i] = m.params.numbered.get(first + i, 0.0) - m.tool_len[i]
    m.rapid(m.src(st), (end[0], end[1], end[2]))


def set_g92(m, st: Step, g: Word) -> None:
    """G92: offsets that make the current point have the given coordinates."""
    words = axis_words(st)
    if not words:
        raise m.error(st.block.line, g.col, "G92 needs at least one axis word")
    for i, w in words.items():
        m.g92[i] = m.base()[i] - m.g5x[i] - m.tlo[i] + m.tool_len[i] - w.value * m.unit(i)
    m.params.numbered[5210] = 1.0
    for i in range(3):
        m.params.numbered[5211 + i] = m.g92[i]


def g10(m, st: Step, g: Word) -> None:
    line, words = st.block.line, st.words
    lw, pw = words.pop("L", None), words.pop("P", None)
    if lw is None:
        raise m.error(line, g.col, "G10 needs L (L1, L2 or L20)")
    L = m.whole(line, lw, "L")
    if pw is None:
        raise m.error(line, lw.col, f"G10 L{L} needs P")
    if "R" in words:
        raise m.error(line, words["R"].col, "G10 R (a rotation of the coordinate system) is not simulated")
    if L in (1, 10, 11):
        tool_entry(m, st, L, m.whole(line, pw, "tool number P"))
        return
    if L not in (2, 20):
        raise m.error(line, lw.col, f"G10 L{L} is not simulated (L1, L2, L10, L11 and L20 are)")
    n = m.whole(line, pw, "coordinate system P")
    if n > 9:
        raise m.error(line, pw.col, f"coordinate system P{pw.raw} must be 0 (the active one) to 9")
    n = n or m.coord
    if n == m.coord and m.comp_side:
        raise m.error(line, pw.col, f"G10 L{L}: cannot change the active coordinate system with cutter radius "
                      "compensation on (G40 first)")
    for i, w in axis_words(st).items():
        if L == 2:
            v = w.value * m.unit(i)
        else:
            v = m.base()[i] - m.g92[i] - m.tlo[i] + m.tool_len[i] - w.value * m.unit(i)
        m.params.numbered[base(n) + i] = v
    if n == m.coord:
        m.g5x = [m.params.numbered.get(base(n) + i, 0.0) for i in range(3)]


def tool_entry(m, st: Step, L: int, tool: int) -> None:
    """G10 L1: tool ``tool``'s X and Z lengths as given; L10: such that the spindle's position would read
    the given coordinates with that length applied in the current system (G5x, G92); L11: in a
    system of G59.3's offsets (LinuxCNC 2.9, measured). The offset in effect changes at the next G43."""
    entry = m.tools.setdefault(tool, {})
    for i, a in ((0, "X"), (2, "Z")):
        if a not in st.words:
            continue
        w = st.words.pop(a)
        if L == 1:
            entry[a] = w.value * m.scale
            continue
        shift = m.g5x[i] + m.g92[i] if L == 10 else m.params.numbered.get(base(9) + i, 0.0)
        entry[a] = m.base()[i] + m.tool_len[i] - shift - w.value * m.unit(i)
