"""The shared block executor every dialect runs on (CNC8x6, ISG, Sinumerik, RS274NGC; the guard on
executed blocks is modal.ModalMachine.count_block).

A dialect is a table of its G and M codes, ``{code: Code(modal group, words, meaning)}`` (compare
CAMotics' ``Codes.cpp`` rows), plus the few hooks where it truly differs. ``Interpreter.execute``
runs one block in a fixed order, as LinuxCNC's rs274ngc ``read_* -> check_* -> convert_*`` does:

1. ``read_words``        the block's words with their values (CNC8x6: R parameters substituted)
2. ``check_g``           G words: known (table), one per modal group; then applied in block order:
                         motion codes select the motion, distance/feed/plane modes switch, the
                         dialect's own codes go to ``g_code`` (default: noted by meaning)
3. ``standalone``        a block that is complete after its G codes (CNC8x6 G98) stops here
4. ``check_m``           M words: known (table); the spindle direction (two in one block refused)
5. ``convert_settings``  spindle, tool and the other non-motion words, before the motion
6. ``convert_nonmodal``  the dialect's non-motion codes (CNC8x6 G73/G10/G09, ISG S.OFFSET)
7. the motion mode       the block's motion code becomes modal
8. ``convert_feed``      F
9. ``convert_motion``    the move itself
10. ``convert_end``      what acts after the move (ISG M05 and subprogram calls; program ends)
"""
from __future__ import annotations

from dataclasses import dataclass, field

from ..canon import Src, Vec3
from .lexer import Block, Word
from .geometry import arc_centre
from .modal import PLANE_AXES, Group, ModalMachine

# Groups every dialect has and the executor applies itself (ModalMachine.common_g).
MOTION = Group.MOTION
COMMON_GROUPS = (Group.DISTANCE, Group.FEED, Group.PLANE)
CENTRE_WORDS = {0: "I", 1: "J", 2: "K"}  # axis index -> its arc-centre offset address


@dataclass(frozen=True)
class Code:
    """One row of a dialect table: the code's modal group (codes of one group exclude each other
    in a block; a code alone in its group gets a group of its own), the addresses it takes besides
    the words every block may carry, and what it means."""

    group: Group
    words: str
    meaning: str


# The rows every word-address dialect shares (ISO 6983): the planes, distance and feed modes the
# executor applies itself; program stop, end and the spindle directions.
ISO_G_CODES = {
    17: Code(Group.PLANE, "", "plane XY"),
    18: Code(Group.PLANE, "", "plane ZX"),
    19: Code(Group.PLANE, "", "plane YZ"),
    90: Code(Group.DISTANCE, "", "absolute"),
    91: Code(Group.DISTANCE, "", "incremental"),
    94: Code(Group.FEED, "", "feed per minute"),
    95: Code(Group.FEED, "", "feed per revolution"),
}
ISO_M_CODES = {
    0: Code(Group.STOP, "", "program stop"),
    1: Code(Group.STOP, "", "optional stop"),
    2: Code(Group.END, "", "program end"),
    3: Code(Group.SPINDLE, "S", "spindle clockwise"),
    4: Code(Group.SPINDLE, "S", "spindle counter-clockwise"),
}


@dataclass
class Step:
    """One block on its way through ``Interpreter.execute``."""

    block: Block
    src: Src
    words: dict[str, Word]  # the words that are neither G nor M, by letter (consumed as they act)
    motion: int | None = None  # the block's motion code
    g: dict[Group, Word] = field(default_factory=dict)  # the dialect's own G codes: group -> word
    groups: dict[Group, Word] = field(default_factory=dict)  # modal group -> its G word
    m: list[tuple[int, Word]] = field(default_factory=list)
    direction: int | None = None  # spindle: +1, -1, 0 (M3/M4/M5), None without one
    speed: Word | None = None  # S, once convert_settings took it
    jump: object = None  # a jump the block asks the run loop for (CNC8x6 G73: target, repeats, word)
    context: object = None  # the dialect's run-loop state for this block (ISG: the call stack)
    done: bool = False  # the block ended early (standalone)
    result: object = None  # what the dialect's hooks hand back to its run loop


class Interpreter(ModalMachine):
    """A ModalMachine driven block by block from the dialect's code tables."""

    G_CODES: dict[int, Code] = {}
    M_CODES: dict[int, Code] = {}

    def __init__(self, name, cfg):
        super().__init__(name, cfg)
        self.motion = 0

    # -- one block ---------------------------------------------------------------------------------
    def execute(self, b: Block, src: Src, context: object = None) -> Step:
        gs, ms, words = self.split_words(self.read_words(b))
        st = Step(b, src, words, context=context)
        self.check_g(st, gs)
        if self.standalone(st):
            st.done = True
            return st
        self.check_m(st, ms)
        self.convert_settings(st)
        self.convert_nonmodal(st)
        if st.motion is not None:
            self.motion = st.motion
        self.convert_feed(st)
        self.convert_motion(st)
        self.convert_end(st)
        return st

    def read_words(self, b: Block) -> list[Word]:
        return b.words

    def check_g(self, st: Step, gs: list[Word]) -> None:
        """Every G word known to the table and alone in its modal group (errors at its column), then
        applied in block order."""
        line = st.block.line
        codes = []
        for g in gs:
            row = self.G_CODES.get(int(g.value)) if g.value == int(g.value) else None
            if row is None:
                raise self.error(line, g.col, f"unknown G code G{g.raw}")
            if row.group in st.groups:
                raise self.error(line, g.col, f"G{g.raw} conflicts with G{st.groups[row.group].raw} in the same block")
            st.groups[row.group] = g
            codes.append((int(g.value), row, g))
        for code, row, g in codes:
            if row.group == MOTION:
                st.motion = code
            elif row.group in COMMON_GROUPS:
                self.common_g(code)
            else:
                self.g_code(st, code, row, g)

    def g_code(self, st: Step, code: int, row: Code, g: Word) -> None:
        """A G code of the dialect's own (not motion, distance, feed or plane): noted by its group."""
        st.g[row.group] = g

    def standalone(self, st: Step) -> bool:
        return False

    def check_m(self, st: Step, ms: list[Word]) -> None:
        if not ms:  # most blocks: no M word, no spindle direction
            return
        for m in ms:
            if m.value != int(m.value) or int(m.value) not in self.M_CODES:
                raise self.error(st.block.line, m.col, f"unknown M code M{m.raw}")
            st.m.append((int(m.value), m))
        st.direction = self.spindle_code(st.block.line, [(c, m.col) for c, m in st.m])

    def m_group(self, st: Step, group: Group) -> list[tuple[int, Word]]:
        """The block's M words (code, word) whose table row is in ``group``."""
        if not st.m:
            return []
        return [(c, m) for c, m in st.m if self.M_CODES[c].group == group]

    def convert_settings(self, st: Step) -> None:
        raise NotImplementedError

    def convert_nonmodal(self, st: Step) -> None:
        pass

    def convert_feed(self, st: Step) -> None:
        raise NotImplementedError

    def convert_motion(self, st: Step) -> None:
        raise NotImplementedError

    def convert_end(self, st: Step) -> None:
        pass

    # -- pieces the hooks share --------------------------------------------------------------------
    def check_words(self, line: int, words: dict[str, Word], letters: str, code: int) -> None:
        """Refuse the first word of ``letters`` (in that order) in ``words`` that the G code ``code``
        does not take (its table row's ``Code.words``), at the word's column."""
        takes = self.G_CODES[code].words
        for a in letters:
            if a in words and a not in takes:
                raise self.error(line, words[a].col, f"address {a} has no meaning in a G{code:02d} block")

    def tool_words(self, st: Step, tool_number) -> None:
        """T (with its D) changes the tool; D alone only names an offset (no geometric effect).
        ``tool_number(word)`` checks and returns the tool number."""
        words, line = st.words, st.block.line
        if "T" in words:
            t = words.pop("T")
            number = tool_number(t)
            d = words.pop("D", None)
            self.tool(st.src, number, None if d is None else self.whole(line, d, "offset number"))
        elif "D" in words:
            self.whole(line, words.pop("D"), "offset number")

    def centre_words(self, line: int, words: dict[str, Word], hint: str = "") -> Vec3:
        """The centre of a G2/G3 block from I/J/K (incremental from the start): at least one in the
        plane, none on its normal (errors at the word or at column 1)."""
        a, c, normal = PLANE_AXES[self.plane]
        if not any(CENTRE_WORDS[i] in words for i in (a, c)):
            raise self.error(line, 1, f"circle needs its centre ({CENTRE_WORDS[a]}/{CENTRE_WORDS[c]}{hint})")
        nw = CENTRE_WORDS[normal]
        if nw in words:
            raise self.error(line, words[nw].col, f"{nw} is not in the plane {self.plane} of the circle")
        offsets = {i: words[CENTRE_WORDS[i]].value for i in (a, c) if CENTRE_WORDS[i] in words}
        centre = arc_centre(self.pos, self.plane, self.diameter, offsets)
        return (centre[0], centre[1], centre[2])
