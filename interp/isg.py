"""Beckhoff TwinCAT CNC (ISG kernel) dialect: program structure, control flow, variables,
``#`` commands, global subprograms, work offsets and G33 with I/J/K leads.

A file holds a main program ``%name`` ended by M30 and any number of local subprograms ``%L name``
ended by M29 (or M17), called with ``LL name``; ``L name`` calls a global subprogram file. The text
is read into statements by interp/isg_scan.py (expressions: interp/isg_lang.py) and run here on the
shared block executor (core.Interpreter). See docs/dialects/isg.md for what the simulator assumes
where the manual is silent.
"""
from __future__ import annotations

import math
import os
import re
import unicodedata

from . import canon
from .canon import Src
from .core.files import Unreadable, find_subprogram, read_bounded
from .core.frames import IDENTITY, Affine, turn
from .core import Code, FullCircle, Group, Interpreter, RadiusTooSmall, Step, radius_centre
from .errors import CutsimError
from .isg_commands import command
from . import isg_fast
from .isg_lang import SCOPES, truth
from .isg_scan import LIMITS, Ctrl, IsgBlock, Section, expand_macros, nfc, parse, scan
from .lexer import COORD_LIMIT, Word, check_range, fmt_count
from .compensation import compensate_records
from .modal import AXES, PLANE_AXES, InterpConfig

class _EveryName:
    """Contains every name (macros after a skipped external subprogram)."""

    def __contains__(self, name) -> bool:
        return True


_EVERY_NAME = _EveryName()

# V.G.NP[i].V.X (zero offset i = 1..6, G54..G59) and V.G.NP_AKT.V.X (the active one), X/Y/Z only
# V.G.@P[i].VALID: in a cycle, 1 when its call programmed @Pi (manual, error ID 21544)
VALID_VAR = re.compile(r"V\.G\.@P\[(\d+)\]\.VALID")
ZERO_VAR = re.compile(r"V\.G\.NP(?:\[(\d+)\]|_AKT)\.V\.([XYZ])")

G_CODES = {
    0: Code(Group.MOTION, "XYZ", "rapid"),
    1: Code(Group.MOTION, "XYZF", "linear feed"),
    2: Code(Group.MOTION, "XYZIJKF", "clockwise arc, centre I/J/K from the start"),
    3: Code(Group.MOTION, "XYZIJKF", "counter-clockwise arc, centre I/J/K from the start"),
    17: Code(Group.PLANE, "", "plane XY"),
    18: Code(Group.PLANE, "", "plane ZX"),
    19: Code(Group.PLANE, "", "plane YZ"),
    33: Code(Group.MOTION, "XYZIJK", "thread, lead on I/J/K (mm/rev)"),
    40: Code(Group.RADIUS_COMP, "", "tool radius compensation off"),
    41: Code(Group.RADIUS_COMP, "", "tool radius compensation left"),
    42: Code(Group.RADIUS_COMP, "", "tool radius compensation right"),
    51: Code(Group.DIAMETER, "", "diameter programming on (lathe)"),
    52: Code(Group.DIAMETER, "", "diameter programming off"),
    53: Code(Group.ZERO_OFFSET, "", "zero offset off"),
    **{n: Code(Group.ZERO_OFFSET, "", f"zero offset G{n}") for n in range(54, 60)},
    90: Code(Group.DISTANCE, "", "absolute"),
    91: Code(Group.DISTANCE, "", "incremental"),
    92: Code(Group.REFERENCE, "XYZ", "reference point offset"),
    94: Code(Group.FEED, "", "feed per minute"),
    95: Code(Group.FEED, "", "feed per revolution"),
    161: Code(Group.CENTRE, "", "circle centre absolute"),
    162: Code(Group.CENTRE, "", "circle centre relative to the start"),
    71: Code(Group.UNITS, "", "millimetres"),
    70: Code(Group.UNITS, "", "inches"),
    25: Code(Group.TRC_TRANSITION, "", "linear transitions at outside corners with tool radius compensation"),
    26: Code(Group.TRC_TRANSITION, "", "circular transitions at outside corners with tool radius compensation"),
    138: Code(Group.TRC_SELECTION, "", "direct selection/deselection of tool radius compensation"),
    139: Code(Group.TRC_SELECTION, "", "indirect selection/deselection of tool radius compensation"),
    20: Code(Group.MIRROR, "", "mirroring off"),
    21: Code(Group.MIRROR, "", "mirroring of X (on the Y axis)"),
    22: Code(Group.MIRROR, "", "mirroring of Y (on the X axis)"),
    23: Code(Group.MIRROR, "", "mirroring of X and Y"),
    351: Code(Group.MIRROR_AXES, "XYZ", "mirroring of the axes given (-1 on, 1 off)"),
    68: Code(Group.ROTATION, "XYZR", "contour rotation by R about X/Y in the plane"),
    69: Code(Group.ROTATION, "", "contour rotation off"),
}
MIRRORS = {20: (False, False), 21: (True, False), 22: (False, True), 23: (True, True)}
# G codes that do not change the tool path (TwinCAT CNC programming manual, "G functions"):
# accepted with one warning each. Those in G_AXIS_PARAMS take axis words as percentages or limits.
G_HARMLESS = {
    4: "dwell time", 8: "acceleration at block start", 9: "deceleration at block end",
    10: "constant feed with tool radius compensation", 11: "adapted feed with tool radius compensation",
    12: "corner deceleration off", 13: "corner deceleration on",
    60: "exact stop", 61: "polynomial contouring (blends corners within the contour tolerance)",
    63: "tapping without compensating chuck", 66: "synchronise cycle at block end",
    96: "constant cutting speed", 97: "constant spindle speed", 98: "negative software limit switches",
    99: "positive software limit switches", 129: "G00 velocity weighting", 130: "axis acceleration weighting",
    131: "acceleration weighting", 132: "axis ramp time weighting", 133: "ramp time weighting",
    134: "geometric ramp time weighting", 164: "circle centre correction", 193: "time-related feed interpolation",
    293: "path-related feed interpolation", 230: "axis G00 acceleration weighting",
    231: "G00 acceleration weighting", 233: "G00 ramp time weighting", 333: "axis feedhold acceleration weighting",
    334: "feedhold acceleration weighting", 900: "acceleration on block transitions", 901: "acceleration on block transitions",
    359: "exact stop mode", 360: "exact stop mode",
    260: "polynomial contouring mode", 261: "polynomial contouring mode", 93: "feed as machining time",
}

G_AXIS_PARAMS = {4, 98, 99, 130, 132, 230, 333}
# selection/deselection methods of tool radius compensation the simulator does not model: they only
# act when G41/G42 is selected or deselected, which is then refused (G138 direct and G139 indirect are)
TRC_METHODS = {5: "tangential selection/deselection", 236: "direct selection/deselection on the path",
               237: "perpendicular selection/deselection", 238: "inside corner selection",
               239: "direct selection/deselection without a block"}
# G codes that change the tool path in a way the simulator does not model: exit 2 naming them
G_NOT_MODELLED = {
    101: "measuring offsets into the zero offsets", 102: "measuring offsets out of the zero offsets",
    74: "homing (a move to the reference point)", 100: "measuring", 106: "measuring", 310: "measuring",
    303: "circle in space", 150: "spline", 151: "spline",
}
# implicit subroutine calls (manual: "Implicit subroutine calls (G80-G89/G800..)"): each runs the global
# subprogram the machine maker configures for it once, at the end of its block ("no modal effect")
IMPLICIT_CALLS = set(range(80, 90)) | set(range(800, 820))
M_CODES = {
    0: Code(Group.STOP, "", "program stop"),
    1: Code(Group.STOP, "", "optional stop"),
    2: Code(Group.END, "", "program end"),
    3: Code(Group.SPINDLE, "S", "spindle clockwise"),
    4: Code(Group.SPINDLE, "S", "spindle counter-clockwise"),
    5: Code(Group.SPINDLE, "", "spindle stop (after the motion)"),
    6: Code(Group.TOOL, "TD", "tool change"),
    7: Code(Group.COOLANT, "", "coolant"),
    8: Code(Group.COOLANT, "", "coolant"),
    9: Code(Group.COOLANT, "", "coolant off"),
    17: Code(Group.END, "", "subprogram end"),
    29: Code(Group.END, "", "subprogram end"),
    30: Code(Group.END, "", "program end"),
}
LEADS = {"I": "X", "J": "Y", "K": "Z"}
MIN_LEAD = 0.0001  # mm/rev: the programming resolution
MAX_CALL_DEPTH = 20  # subprograms (local and global) open at once
MAX_SUB_BYTES = 10_000_000
SUB_EXTENSIONS = ("", ".nc", ".NC", ".Nc", ".ISG", ".isg")

_UMLAUTS = str.maketrans({"ä": "ae", "ö": "oe", "ü": "ue", "ß": "ss", "Ä": "Ae", "Ö": "Oe", "Ü": "Ue"})


def _folds(name: str) -> set[str]:
    """Spellings a name may have been meant as: case folded, umlauts as digraphs or stripped."""
    n = nfc(name)
    digraph = n.translate(_UMLAUTS).casefold()
    stripped = "".join(c for c in unicodedata.normalize("NFKD", n) if not unicodedata.combining(c)).casefold()
    return {n.casefold(), digraph, stripped}


_NOT_EXTRA = frozenset("DEFGHIJKLMNOPQRSTXYZ")  # letters Isg.extra_axes leaves alone


class Frame:
    """One running program level: its file, local subprograms, V.L. variables, call parameters."""

    __slots__ = ("name", "local", "vl", "params", "stack", "calls", "modal", "cycle")

    def __init__(self, name, local, params, stack, calls, cycle=False):
        self.name, self.local, self.params, self.stack, self.calls = name, local, params, stack, calls
        self.cycle = cycle  # a cycle call (L CYCLE, LL CYCLE, an implicit call with an argument list)
        self.vl: dict = {}
        self.modal: tuple | None = None  # L CYCLE [.. MODAL_MOVE ..] of this level: (file name, column, params)


class Isg(Interpreter):
    G_CODES = G_CODES
    M_CODES = M_CODES

    def __init__(self, name: str, cfg: InterpConfig):
        super().__init__(name, cfg)
        self.lead: tuple[float, str] | None = None  # (mm per revolution, axis letter)
        self.offset = 0.0  # S.OFFSET, degrees
        self.ended = False
        self.last_block: IsgBlock | None = None
        self.params: dict[str, float | str] = {f"P{k}": float(v) for k, v in cfg.parameters.items()}
        self.vars: dict[str, float | str] = {}  # V.P., V.S. and written V.E./V.G.
        self.declared: dict[str, tuple] = {}  # V.P./V.S. name -> dims
        self.frame: Frame | None = None
        self.zero = (0.0, 0.0, 0.0)  # G54..G59 offset
        self.npv: dict[int, list] = {}  # zero offsets the program wrote (V.G.NP[i].V.X = ..): i -> [x, y, z]
        self.g92 = [0.0, 0.0, 0.0]
        self.cs: list[tuple[float, float, float]] = []  # active #CS translations (a stack)
        self.cs_defs: dict[int, tuple[float, float, float]] = {}  # #CS DEF: id -> translation
        self.cs_last: int | None = None  # the id #CS DEF or #CS ON [..] defined last
        self.mcs = False  # #MCS ON: machine coordinates (no offsets)
        self.centre_abs = False  # G161
        self.extra_pos: dict[str, float] = {a: 0.0 for a in cfg.axes}
        self.warned: set = set()
        self.files: dict[str, tuple] = {}  # global subprogram files read: path -> (main, local)
        self.implicit_files: dict[str, str] = {}  # #FILE NAME [G80 = "file"]: G code -> file name
        # [machine] external_subprograms by their names without extension ("0_INICIO_PROG", "G803")
        self.external_stems = frozenset(os.path.splitext(n)[0] or n for n in cfg.external_subprograms)
        self.external_skipped: str | None = None  # the first declared external subprogram skipped
        # tool radius compensation (G40/G41/G42): records between selection and deselection are buffered
        self.tool_no: int | None = next(iter(cfg.tool_radii), None)
        self.d_zero = False  # D0: no tool compensation
        self.comp = 40
        self.comp_buf: list | None = None
        self.comp_radius = 0.0
        self.comp_plane = ""
        self.comp_off = False  # G40 programmed: the next motion in the plane departs
        self.trc_linear = True  # G25 (default) / G26
        self.trc_method: tuple = (139, None)
        self.r_col = 1  # column of the R word of the block being converted (1: none there)
        self.circle_r: float | None = None  # R (circle radius, modal)  # G139 indirect (default), G138 direct, or an unmodelled one
        # rotated and mirrored program coordinates (isg_commands.frame): #ROTATION, G20..G23/G351, #CS about Z
        self.rotation: tuple | None = None  # (angle, plane, centre 1, centre 2)
        self.mirror = [False, False, False]
        self.turned = False  # a rotation or a mirroring is active: targets go through isg_commands.frame
        self.turned_linear = IDENTITY  # the frame's linear part
        self.comp_flip = 1.0  # -1: the compensation side swaps (mirrored plane at selection)

    # -- messages ----------------------------------------------------------------------------------
    def warn_once(self, key, src: Src, message: str) -> None:
        if key not in self.warned:
            self.warned.add(key)
            self.warn(src, message)

    # -- program structure -----------------------------------------------------------------------
    def run(self, text: str) -> canon.Program:
        self.macros: dict[str, str] = {}
        main, local = parse(self.name, text, self.cfg.max_blocks, self.macros, isg_fast.read_plain)
        self.check_count(main, local)
        self.frame = Frame(self.name, local, {}, (), ())
        self.declare(main)
        if main.title:
            t = main.title if len(main.title) <= 60 else main.title[:57] + "..."
            self.warn(Src(self.name, main.line, main.col), f"the text after the program name '%{main.name}' "
                      f"('{t}') is taken as the program's title (write a title in parentheses)")
        for other in main.others:
            self.warn(Src(self.name, other.line, other.col), f"a further main program '%{other.name}' in this file "
                      f"is not run (the file runs its first main program, '%{main.name}')")
        self.section(main)
        if self.comp_buf is not None:
            self.flush_comp(departure=False)
        if not self.ended and self.last_block is not None:
            b = self.last_block
            self.warn(Src(self.name, b.line, 1, getattr(b, "label", "")), "the main program ends without M30")
        self.program.blocks = self.executed
        self.program.final_position = tuple(self.pos)
        return self.program

    def check_count(self, main: Section, local: dict) -> None:
        """Without control flow, jumps or global calls, the blocks a program executes are known before
        it runs: refuse one whose count exceeds ``cfg.max_blocks`` at the main program's heaviest call."""
        if main.flow or any(s.flow for s in local.values()):
            return
        counts = static_counts(main, local)
        if counts is None:
            return
        limit = self.cfg.max_blocks
        total, _ = counts[None]
        if total <= limit:
            return
        heaviest = None
        for b in main.blocks:
            if b.call is not None and (heaviest is None or counts[b.call[0]][0] > counts[heaviest.call[0]][0]):
                heaviest = b
            if _ends_program(b) or (b.call is not None and counts[b.call[0]][1]):
                break
        where = (1, 1) if heaviest is None else (heaviest.line, heaviest.call[1])
        what = "" if heaviest is None else (f"LL {heaviest.call[0]} executes {fmt_count(counts[heaviest.call[0]][0])} "
                                             "blocks (its subprogram calls counted): ")
        raise self.error(*where, f"{what}the program would execute {fmt_count(total)} blocks, more than the limit of "
                         f"{limit:,} set by [simulation] max_blocks")

    def block_limit(self, b) -> CutsimError:
        return self.error(b.line, 1, f"more than {self.cfg.max_blocks:,} blocks executed (the limit is [simulation] "
                          "max_blocks): a loop or jump that does not end?")

    def declare(self, sec: Section | IsgBlock) -> None:
        """#VAR declarations of a program level (at its start: each name with its first declaration),
        or of one #VAR block where the run reaches it (after the level's first block: declared again,
        with that block's values): V.L. into its frame, V.P./V.S. program-wide (also from a subprogram:
        the manual creates user variables in the main program or a subprogram, V.P. ones global)."""
        for d in sec.decls:
            size = math.prod(d.dims) if d.dims else 1
            values = [f(self) for f in d.init]
            if len(values) > size:
                raise self.error(d.line, d.col, f"{d.name} has {size} element(s), {len(values)} values given")
            if d.scope == "L":
                store = self.frame.vl
            else:
                store = self.vars
                self.declared[d.name] = d.dims
            store[d.name] = d.dims
            for k, key in enumerate(_element_keys(d.name, d.dims)):
                store[key] = values[k] if k < len(values) else (values[0] if len(values) == 1 and not d.dims else 0.0)

    def section(self, sec: Section) -> None:
        """Run a program body with its control flow; returns at M29/M17, sets ``self.ended`` at M30."""
        blocks = sec.blocks
        pc, n = 0, len(blocks)
        fr = self.frame
        while pc < n:
            b = blocks[pc]
            self.count_block(b)
            if isinstance(b, Ctrl):
                pc = self.control(sec, b, pc)
                continue
            self.last_block = b
            if b.decls:
                self.declare(b)
                pc += 1
                continue
            if b.deferred:
                b = self.expand(b)
                if b is None:
                    pc += 1
                    continue
            try:
                ret = self.block(b, fr)
            except CutsimError as e:
                if fr.stack and e.line == b.line and e.program == self.name and "(in subprogram" not in e.message:
                    raise CutsimError(e.program, e.line, e.col, f"{e.message} (in subprogram '{fr.stack[-1]}' "
                                      f"called from line {fr.calls[-1][1]})") from None
                raise
            if self.ended or ret:
                return
            if fr.modal is not None and _moves(b):
                self.modal_cycle(b, fr)
                if self.ended:
                    return
            if b.goto is not None and (b.cond is None or truth(b.cond(self))):
                pc = self.jump(sec, b)
                continue
            pc += 1

    def expand(self, b: IsgBlock):
        """A line whose macro was not defined when it was read: expanded and read now."""
        used: list = []
        # after a declared external subprogram was skipped, a macro no file defines is taken to be
        # one it defines (a WAAM cell's start program defines "Encender_arco"): every name passes
        external = _EVERY_NAME if self.external_skipped else self.cfg.external_subprograms
        nb = scan(self.name, b.line, expand_macros(self.name, b.line, b.deferred, self.macros, external, used))
        for name in used:
            src = Src(self.name, b.line, 1, b.label, self.frame.calls)
            if name.upper() in self.cfg.external_subprograms:
                why = "is declared external in the setup ([machine] external_subprograms): the machine defines it"
            else:
                why = (f"is defined by no file: taken to be defined by the external {self.external_skipped} "
                       "(declared in [machine] external_subprograms and not simulated)")
            self.warn_once(("macro", name.upper()), src, f"macro \"{name}\" {why}; its effect is not simulated "
                           "(it is taken to move nothing)")
        if isinstance(nb, Ctrl):
            raise self.error(b.line, nb.col, f"${nb.kw} from a macro is not supported by the simulator")
        return nb

    def jump(self, sec: Section, b: IsgBlock) -> int:
        kind, target, col = b.goto
        if kind == "S":
            label = target
        else:
            v = target(self)
            if kind == "V" and isinstance(v, str):
                label = f"[{v.strip().upper()}]"
            elif isinstance(v, str) or v != int(v) or v < 0:
                raise self.error(b.line, col, f"$GOTO N{v}: a block number is a whole number")
            else:
                label = f"N{int(v)}"
        if label in sec.labels:
            return sec.labels[label]
        if label + "?" in sec.labels and label.startswith("N"):
            return sec.labels[label + "?"]
        raise self.error(b.line, col, f"$GOTO {label}: no label {label}{':' if label.startswith('N') else ''} in this "
                         "program level (a jump stays in its main program or subprogram)")

    def control(self, sec: Section, st: Ctrl, pc: int) -> int:
        """Run one control statement; the index of the next statement."""
        kw, m, blocks = st.kw, st.match, sec.blocks
        if kw == "IF":
            if truth(st.expr(self)):
                return pc + 1
            for k in m["branches"]:
                br = blocks[k]
                if br.kw == "ELSE" or truth(br.expr(self)):
                    return k + 1
            return m["end"] + 1
        if kw in ("ELSEIF", "ELSE"):
            return m["end"] + 1  # the branch before it ran: leave the $IF
        if kw in ("ENDIF", "DO", "CASE", "DEFAULT", "ENDSWITCH"):
            return pc + 1
        if kw == "WHILE":
            return pc + 1 if truth(st.expr(self)) else m["end"] + 1
        if kw == "ENDWHILE":
            return m["open"]
        if kw == "ENDDO":
            return m["open"] + 1 if truth(st.expr(self)) else pc + 1
        if kw == "FOR":
            start = self.number(st.exprs[0](self), st, "$FOR start")
            self.set_counter(st, start)
            return pc + 1 if self.for_ok(st, start) else m["end"] + 1
        if kw == "ENDFOR":
            head = blocks[m["open"]]
            v = self.number(self.get_counter(head), head, "$FOR counter") + self.for_step(head)
            self.set_counter(head, v)
            return m["open"] + 1 if self.for_ok(head, v) else pc + 1
        if kw == "SWITCH":
            v = st.expr(self)
            default = None
            for k in m["branches"]:
                br = blocks[k]
                if br.kw == "DEFAULT":
                    default = k
                elif br.expr(self) == v:
                    return k + 1
            return (default + 1) if default is not None else m["end"] + 1
        if kw == "BREAK":
            return m["end"] + 1
        if kw == "CONTINUE":
            return m["end"]  # the loop's end statement tests and steps
        raise AssertionError(kw)  # pragma: no cover

    def number(self, v, st, what: str) -> float:
        if isinstance(v, str):
            raise self.error(st.line, st.col, f"{what}: \"{v}\" is not a number")
        return v

    def for_step(self, st: Ctrl) -> float:
        step = self.number(st.exprs[2](self), st, "$FOR step")
        if step == 0:
            raise self.error(st.line, st.col, "$FOR step 0 never ends the loop")
        return step

    def for_ok(self, st: Ctrl, v: float) -> bool:
        end = self.number(st.exprs[1](self), st, "$FOR end")
        return v <= end if self.for_step(st) > 0 else v >= end

    def set_counter(self, st: Ctrl, v: float) -> None:
        if st.var[0] == "P":
            self.params[st.var[1]] = v
        else:
            self.write_var(st.var[1], st.var[2](self), v, st.line, st.var[3])

    def get_counter(self, st: Ctrl):
        if st.var[0] == "P":
            return self.read_param(st.var[1], st.line, st.var[3])
        return self.read_var(st.var[1], st.var[2](self), st.line, st.var[3])

    # -- variables and parameters (isg_lang closures call these) --------------------------------------
    def read_param(self, key: str, line: int, col: int):
        store = self.frame.params if key.startswith("@") else self.params
        if key not in store:
            what = "call parameter" if key.startswith("@") else "parameter"
            raise self.error(line, col, f"{what} {key} is read before it is assigned a value")
        return store[key]

    def read_var(self, scope: str, key: str, line: int, col: int):
        if scope == "L":
            if key in self.frame.vl:
                return self._element(self.frame.vl, key, line, col)
            raise self.error(line, col, f"{key} is not declared in this program level (declare it in #VAR ... #ENDVAR)")
        if scope in ("P", "S"):
            if key in self.vars:
                return self._element(self.vars, key, line, col)
            raise self.error(line, col, f"{key} is not declared (declare it in the main program's #VAR ... #ENDVAR)")
        m = ZERO_VAR.fullmatch(key) if scope == "G" else None
        if m:
            return self.zero_table(m, line, col)[0][AXES.index(m.group(2))]
        if key == "V.G.WZ_AKT.R" and key not in self.vars and (self.d_zero or self.tool_no in self.cfg.tool_radii):
            return self.active_radius(line, col)
        m = VALID_VAR.fullmatch(key) if scope == "G" else None
        if m:
            if not self.frame.cycle:
                raise self.error(line, col, f"{key} is read outside a cycle (the controller's error 21544: it tells "
                                 "a cycle whether its call programmed @P" + m.group(1) + ")")
            return 1.0 if f"@P{int(m.group(1))}" in self.frame.params else 0.0
        if key in self.vars:
            return self.vars[key]
        if key in self.cfg.variables:
            return self.cfg.variables[key]
        what = SCOPES.get(scope, "controller")
        raise self.error(line, col, f"{key} ({what} variable) is not known to the simulator (give it a value in the "
                         f"setup: [variables] \"{key}\" = ...)")

    def exists(self, scope: str, key: str) -> bool:
        """EXIST[V.x.NAME]: the variable is declared (or, for V.E./V.G., known from the setup)."""
        if scope == "L":
            return key in self.frame.vl
        return key in self.vars or (scope not in ("P", "S") and key in self.cfg.variables)

    def _element(self, store: dict, key: str, line: int, col: int):
        v = store[key]
        if isinstance(v, tuple):
            raise self.error(line, col, f"{key} is an array: give its index ({key}[0])")
        return v

    def write_var(self, scope: str, key: str, value, line: int, col: int) -> None:
        if scope == "L":
            store = self.frame.vl
        elif scope in ("P", "S"):
            store = self.vars
        else:
            if key == "V.G.WZ_AKT.R" and self.comp_buf is not None:
                raise self.error(line, col, f"{key} = ...: changing the tool radius while tool radius compensation is "
                                 "active is not modelled by the simulator")
            if key.startswith("V.G.WZ_AKT.") and key != "V.G.WZ_AKT.R":
                raise self.error(line, col, f"{key} = ...: changing the active tool's data (length, offsets) moves the "
                                 "tool tip in a way the simulator does not model")
            m = ZERO_VAR.fullmatch(key) if scope == "G" else None
            if m:
                self.write_zero(m, value, line, col)
                return
            if VALID_VAR.fullmatch(key):
                raise self.error(line, col, f"{key} is read-only (it tells a cycle whether its call programmed the "
                                 "parameter)")
            self.vars[key] = value  # an external or global variable the program sets
            return
        if key not in store:
            base = key.split("[", 1)[0]
            if base in store and isinstance(store[base], tuple):
                raise self.error(line, col, f"{key}: index outside the array {base}{''.join(f'[{d}]' for d in store[base])}")
            if scope == "P" and base == key and self.external_skipped:
                # a timber CAM program writes V.P.CHARGENLAENGE after L steuer_TW.up (external), which declares it
                self.warn_once(("vp", key), Src(self.name, line, col, "", self.frame.calls),
                               f"{key} is declared by no #VAR: taken to be declared by the external "
                               f"{self.external_skipped} (declared in [machine] external_subprograms, not simulated)")
                store[key] = value
                return
            raise self.error(line, col, f"{key} is not declared (declare it in #VAR ... #ENDVAR)")
        if isinstance(store[key], tuple):
            raise self.error(line, col, f"{key} is an array: give its index")
        store[key] = value

    def assign(self, target, f, line: int, col: int) -> None:
        value = f(self)
        if target[0] == "P":
            _, kind, idx = target
            if idx is None:
                key = kind
            else:
                n = idx(self)
                if isinstance(n, str) or n != int(n) or n < 0:
                    raise self.error(line, col, f"parameter number {n} must be a whole number")
                key = f"{kind}{int(n)}"
            if key.startswith("@"):
                self.frame.params[key] = value
            else:
                self.params[key] = value
        else:
            _, scope, keyf = target
            self.write_var(scope, keyf(self), value, line, col)

    # -- one block (core.Interpreter.execute runs the steps in order) --------------------------------
    def block(self, b: IsgBlock, fr: Frame) -> bool:
        """Execute one block; True when it returns from a subprogram."""
        src = Src(self.name, b.line, 1, b.label, fr.calls)
        if isg_fast.plain_block(self, b, src, fr):  # the common G00/G01 block the short way (interp/isg_fast.py)
            return False
        return bool(self.execute(b, src, fr).result)

    def read_words(self, b: IsgBlock) -> list[Word]:
        """Assignments and words in their order: an expression sees the assignments before it."""
        if len(b.items) == len(b.words):
            return b.words
        out = []
        for it in b.items:
            if it[0] == "w":
                out.append(it[1])
            elif it[0] == "x":
                _, letter, f, raw, col = it
                v = f(self)
                if isinstance(v, str):
                    raise self.error(b.line, col, f"{letter}{raw} is the string \"{v}\", not a number")
                lim, unit = LIMITS.get(letter, (COORD_LIMIT, "mm"))
                check_range(self.name, b.line, col, f"{letter}{raw} = {v:g}", v, -lim, lim, unit)
                out.append(Word(letter, v, f"{v:g}", col))
            else:
                _, target, f, col = it
                self.assign(target, f, b.line, col)
        return out

    def check_g(self, st: Step, gs: list[Word]) -> None:
        """The dialect's G table; G codes that only get a warning; implicit subroutine calls (G80..G89,
        G800..G819); the rest are errors naming the code."""
        line = st.block.line
        keep = []
        for g in gs:
            code = int(g.value) if g.value == int(g.value) else None
            if code is None:
                raise self.error(line, g.col, f"unknown G code G{g.raw}")
            if code in TRC_METHODS:
                if code == 5:
                    st.g[Group.TRC_SELECTION] = g  # G5 tangential: non-modal, this block only
                else:
                    self.trc_method = (code, g)
                continue
            if code in G_HARMLESS:
                self.warn_once(("G", code), st.src, f"G{g.raw} ({G_HARMLESS[code]}) does not change the tool path: "
                               "accepted, not simulated")
                if g.col in st.block.gvalues:
                    st.block.gvalues[g.col](self)  # its value is read (errors in it are errors), not used
                for f in st.block.args.get(g.col, ()):
                    f(self)
                if code in G_AXIS_PARAMS:
                    for a in "XYZABCUVWF" + ("SK" if code == 4 else ""):
                        st.words.pop(a, None)
                continue
            if code == 80 and self.g80_plain(g, st.block):
                self.warn_once(("G", 80), st.src, "G80 (modal cycle off) does not change the tool path: accepted")
                continue
            if code in IMPLICIT_CALLS:
                if st.result is not None:
                    raise self.error(line, g.col, "two implicit subroutine calls in one block")
                st.result = ("implicit", code, g)
                continue
            if code in self.G_CODES:
                if g.col in st.block.args:
                    raise self.error(line, g.col, f"G{g.raw} takes no argument list '[...]'")
                if g.col in st.block.gvalues:
                    raise self.error(line, g.col, f"G{g.raw} takes no value '= ...'")
                keep.append(g)
                continue
            if code in G_NOT_MODELLED:
                raise self.error(line, g.col, f"G{g.raw} ({G_NOT_MODELLED[code]}) is not modelled by the simulator "
                                 "(exit rather than a wrong tool path)")
            raise self.error(line, g.col, f"unknown G code G{g.raw}")
        super().check_g(st, keep)

    def g_code(self, st: Step, code: int, row: Code, g: Word) -> None:
        line = st.block.line
        if row.group is Group.DIAMETER:  # G51/G52 act at once
            if self.cfg.machine_kind != "lathe":
                raise self.error(line, g.col, f"G{g.raw} (diameter programming) needs a lathe")
            self.set_diameter(code == 51)
        elif row.group is Group.ZERO_OFFSET:
            self.zero_offset(st, code, g)
        elif row.group is Group.TRC_TRANSITION:
            self.trc_linear = code == 25
        elif row.group is Group.TRC_SELECTION:
            self.trc_method = (code, g)
        elif row.group is Group.CENTRE:
            self.centre_abs = code == 161
        elif row.group is Group.MIRROR:
            self.mirror[0], self.mirror[1] = MIRRORS[code]
            self.frame_changed(line, g.col)
            if code != 20:
                self.warn_once(("G", code), st.src, f"G{g.raw} mirrors the program ({row.meaning}; on this controller "
                               "it is not the millimetre input of other controls)")
        elif code == 69:
            self.rotation = None
            self.frame_changed(line, g.col)
        elif row.group is Group.UNITS:
            if code == 70:
                raise self.error(line, g.col, "G70 (inch programming) is not modelled: the simulator works in millimetres")
        else:  # G41/G42/G40, G351, G68, G92: act in convert_nonmodal / convert_motion
            st.g[row.group] = g

    def zero_table(self, m, line: int, col: int) -> tuple[list, int | None]:
        """The zero offset V.G.NP[i] (i = 1..6: G54..G59) or V.G.NP_AKT (the active one) a variable
        names: (its X, Y, Z values, i or None for NP_AKT)."""
        if m.group(1) is None:
            return list(self.zero), None
        i = int(m.group(1))
        if not 1 <= i <= 6:
            raise self.error(line, col, f"V.G.NP[{i}]: the zero offsets are V.G.NP[1] (G54) .. V.G.NP[6] (G59)")
        if i not in self.npv:
            self.npv[i] = list(self.cfg.work_offsets.get(f"G{53 + i}", (0.0, 0.0, 0.0)))
        return self.npv[i], i

    def write_zero(self, m, value, line: int, col: int) -> None:
        """V.G.NP[i].V.X = .. writes the zero offset table (used from the next G54..G59 selection on);
        V.G.NP_AKT.V.X = .. the active zero offset (at once), as the manual's examples do."""
        if isinstance(value, str):
            raise self.error(line, col, f"a zero offset is a number, not the string \"{value}\"")
        vals, i = self.zero_table(m, line, col)
        vals[AXES.index(m.group(2))] = float(value)
        if i is None:
            self.zero = tuple(vals)

    def zero_offset(self, st: Step, code: int, g: Word) -> None:
        if code == 53:
            self.zero = (0.0, 0.0, 0.0)
            return
        key = f"G{code}"
        if code - 53 in self.npv:
            self.zero = tuple(self.npv[code - 53])
        elif key in self.cfg.work_offsets:
            self.zero = tuple(self.cfg.work_offsets[key])
        else:
            self.zero = (0.0, 0.0, 0.0)
            self.warn_once(("zero", key), st.src, f"{key}: no offset given in the setup ([work_offsets] {key} = "
                           "[x, y, z]); offset 0 assumed")

    def check_m(self, st: Step, ms: list[Word]) -> None:
        keep = []
        for m in ms:
            code = int(m.value) if m.value == int(m.value) else None
            if code in self.M_CODES:
                if m.col in st.block.gvalues:
                    raise self.error(st.block.line, m.col, f"M{m.raw} takes no value '= ...'")
                keep.append(m)
            elif code is not None and code in self.cfg.m_functions:
                continue  # a machine function the setup declares: no geometric effect
            else:
                raise self.error(st.block.line, m.col, f"unknown M code M{m.raw}: not an ISG M function and not declared "
                                 f"as a machine function (declare it in the setup: [machine] m_functions = [{m.raw}])")
        super().check_m(st, keep)
        ends = self.m_group(st, Group.END)
        if len(ends) > 1:
            raise self.error(st.block.line, ends[1][1].col, "two program-end M codes in one block")

    def convert_settings(self, st: Step) -> None:
        b, words = st.block, st.words
        for w in [w for w in b.words if w.letter == "H"]:
            if w.value != int(w.value) or int(w.value) not in self.cfg.h_functions:
                raise self.error(b.line, w.col, f"H{w.raw} is not a machine function the setup declares "
                                 f"([machine] h_functions = [{w.raw}])")
        words.pop("H", None)
        if "D" in words:
            self.d_zero = words["D"].value == 0
        speed = st.speed = words.pop("S", None)
        if speed is not None and speed.value < 0:
            raise self.error(b.line, speed.col, "spindle speed S must not be negative")
        if st.direction != 0 and (st.direction is not None or speed is not None):
            self.spindle(st.src, st.direction, None if speed is None else speed.value)
        self.tool_words(st, lambda t: self.tool_number(b, t))

    def tool_number(self, b: IsgBlock, t: Word) -> int:
        if t.value != int(t.value) or t.value < 0:
            raise self.error(b.line, t.col, f"tool number T{t.raw} must be a whole number")
        return int(t.value)

    def convert_nonmodal(self, st: Step) -> None:
        for w in st.block.offsets:
            if not 0.0 <= w.value < 360.0:
                raise self.error(st.block.line, w.col, f"S.OFFSET={w.raw} is outside the spindle's modulo range "
                                 "(0 <= offset < 360 degrees)")
            self.offset = w.value
        for name, text, col in st.block.commands:
            command(self, st, name, text, col)
        if Group.REFERENCE in st.g:
            self.set_position(st)
        if Group.MIRROR_AXES in st.g:
            self.mirror_axes(st, st.g[Group.MIRROR_AXES])
        if Group.ROTATION in st.g:
            self.g68(st, st.g[Group.ROTATION])

    def set_position(self, st: Step) -> None:
        """G92 X.. Y.. Z..: the reference point offset (an additive zero offset) of the axes given, set
        under G90 and added under G91 (manual: "Reference point offset (G92)"); G92 X0 resets it."""
        for i, a in enumerate(AXES):
            w = st.words.pop(a, None)
            if w is not None:
                self.g92[i] = w.value if self.absolute else self.g92[i] + w.value

    def convert_feed(self, st: Step) -> None:
        if "F" in st.words:
            f = st.words.pop("F")
            if self.motion == 33:
                raise self.error(st.block.line, f.col, "F has no meaning while G33 is active: the lead is programmed "
                                 "on I, J or K (mm per revolution) and the feed follows from the spindle speed")
            if f.value <= 0:
                raise self.error(st.block.line, f.col, "feed F must be positive")
            self.feed = f.value

    def shift(self) -> tuple[float, float, float]:
        if self.mcs:
            return (0.0, 0.0, 0.0)
        if not self.cs:  # the usual case, without a generator per axis (+ 0.0: what sum() of nothing adds)
            z, g = self.zero, self.g92
            return (z[0] + g[0] + 0.0, z[1] + g[1] + 0.0, z[2] + g[2] + 0.0)
        return tuple(self.zero[i] + self.g92[i] + sum(c[i] for c in self.cs) for i in range(3))

    def target(self, values: dict[int, float], absolute=None):
        """End point (machine values) from axis words: absolute words are shifted by the active zero
        offset, #CS translation and G92; incremental ones add to the position."""
        if self.turned:
            f = self.program_frame()
            p = f.inverse_apply(self.pos)
            for i, v in values.items():
                p[i] = v if self.absolute else p[i] + v
            return f.apply(p)
        end = list(self.pos)
        sh = self.shift()
        for i, v in values.items():
            end[i] = v + sh[i] if self.absolute else self.pos[i] + v
        return (end[0], end[1], end[2])

    # -- rotation and mirroring (#ROTATION, #CS about Z, G20..G23, G351) ------------------------------
    def program_frame(self) -> Affine:
        """The map program coordinates -> machine coordinates. Applied in order: the contour rotation
        about its centre, the mirroring of the program axes, the #CS stack (the last one switched on
        first), the zero offset and G92 (docs/dialects/isg.md, "Rotation and mirroring")."""
        steps = []
        if self.rotation is not None:
            deg, plane, c1, c2 = self.rotation
            a, c, _ = PLANE_AXES[plane]
            cen = [0.0, 0.0, 0.0]
            cen[a], cen[c] = c1, c2
            steps.append(Affine.rotation(deg, a, c, cen))
        if any(self.mirror):
            steps.append(Affine.mirror(self.mirror))
        for cs in reversed(self.cs):
            steps.append(Affine(turn(cs[3], 0, 1), (cs[0], cs[1], cs[2])))
        f = Affine()
        for step in steps:
            f = step.then(f)
        z, g = self.zero, self.g92
        return f.shifted((z[0] + g[0], z[1] + g[1], z[2] + g[2]))

    def frame_changed(self, line: int, col: int) -> None:
        """A rotation, mirroring or #CS changed: whether targets go the long way, and what may not change."""
        self.turned = self.rotation is not None or any(self.mirror) or any(c[3] % 360.0 != 0.0 for c in self.cs)
        lin = self.program_frame().L if self.turned else IDENTITY
        if lin != IDENTITY and self.cfg.machine_kind == "lathe":
            raise self.error(line, col, "rotating or mirroring the program coordinates on a lathe is not modelled by "
                             "the simulator")
        if self.comp_buf is not None and lin != self.turned_linear:
            raise self.error(line, col, "a rotation or mirroring changed while tool radius compensation is active: "
                             "not modelled by the simulator (switch it with G40 first)")
        self.turned_linear = lin

    def g68(self, st: Step, g: Word) -> None:
        """G68 R.. X.. Y.. (G17; G18: Z X, G19: Y Z): contour rotation by R degrees about the absolute
        point of the plane's main axes; an axis not programmed takes the tool's position (manual:
        "Rotate the coordinate system in the plane (G68/G69)")."""
        a, c, n = PLANE_AXES[self.plane]
        r = st.words.pop("R", None)
        if AXES[n] in st.words:
            w = st.words[AXES[n]]
            raise self.error(st.block.line, w.col, f"G68 takes the centre in the axes of the plane {self.plane}, "
                             f"not {AXES[n]}")
        here = self.program_frame().inverse_apply(self.pos) if self.turned else [self.pos[i] - self.shift()[i] for i in range(3)]
        cen = [st.words.pop(AXES[i]).value if AXES[i] in st.words else here[i] for i in (a, c)]
        self.rotation = (0.0 if r is None else r.value, self.plane, cen[0], cen[1])
        self.frame_changed(st.block.line, g.col)

    def mirror_axes(self, st: Step, g: Word) -> None:
        """G351 X-1 Y1 Z+1: mirroring on (-1) or off (1) per axis, modal; G351 stands alone in its block
        (manual: "Mirroring with axis specification (G351)")."""
        line = st.block.line
        given = [(i, st.words.pop(a)) for i, a in enumerate(AXES) if a in st.words]
        if not given:
            raise self.error(line, g.col, "G351 needs at least one axis with -1 (mirroring on) or 1 (off): G351 X-1")
        other = [w for w in st.words.values()] + [m for _, m in st.m]
        if other or len(st.groups) > 1 or st.block.call or st.block.gcall:
            col = other[0].col if other else g.col
            raise self.error(line, col, "G351 must stand alone in its block (only a block number with it)")
        for i, w in given:
            if w.value not in (1.0, -1.0):
                raise self.error(line, w.col, f"G351 {AXES[i]}{w.raw}: the value is -1 (mirroring on) or 1 (off)")
            self.mirror[i] = w.value == -1.0
        self.frame_changed(line, g.col)

    def extra_axes(self, st: Step) -> None:
        if st.words.keys() <= _NOT_EXTRA:  # no A B C U V W nor a named axis: nothing to do
            return
        for a in sorted(k for k in st.words if k in "ABCUVW" or len(k) > 1):
            w = st.words.pop(a)
            if a not in self.cfg.axes:
                raise self.error(st.block.line, w.col, f"axis {a} is not on this machine (declare it in the setup: "
                                 f"[machine] axes = {{ {a} = \"rotary\" }})")
            new = w.value if self.absolute else self.extra_pos[a] + w.value
            if new != self.extra_pos[a]:
                self.warn_once(("axis", a), st.src, f"axis {a} ({self.cfg.axes[a]}) moves: tracked, but it does not "
                               "move the tool or the workpiece in this 3-axis simulation")
            self.extra_pos[a] = new

    # -- tool radius compensation (G40/G41/G42; geometry in interp/compensation.py) -----------------
    def tool(self, src: Src, number: int, offset: int | None) -> None:
        if self.comp_buf is not None and number != self.tool_no:
            raise self.error(src.line, 1, f"tool change (T{number}) while tool radius compensation is active: "
                             "not modelled by the simulator (deselect it with G40 first)")
        self.tool_no = number
        super().tool(src, number, offset)

    def emit(self, rec) -> None:
        if self.comp_buf is not None:
            self.comp_buf.append(rec)
        else:
            self.program.records.append(rec)

    def active_radius(self, line: int, col: int):
        """V.G.WZ_AKT.R read by the program: the active tool's radius, the one G41/G42 use (the
        setup's [[tool]] diameter / 2, 0 after D0); a value the setup's [variables] gives explicitly
        is used instead, with one warning when it differs."""
        r = self.trc_radius()
        given = self.cfg.variables.get("V.G.WZ_AKT.R")
        if given is None:
            return r
        if isinstance(given, str) or abs(given - r) > 1e-9:
            self.warn_once(("WZ_AKT.R", self.tool_no, self.d_zero), Src(self.name, line, col, "", self.frame.calls),
                           f"V.G.WZ_AKT.R: the setup's [variables] value {given!r} is used, but the active tool "
                           f"(T{self.tool_no}{', D0' if self.d_zero else ''}) has the radius {r:g} "
                           "([[tool]] diameter / 2), which tool radius compensation uses")
        return given

    def trc_radius(self) -> float:
        """The active tool's radius: V.G.WZ_AKT.R when the program wrote it, else the setup's tool
        (its diameter / 2); 0 after D0."""
        if "V.G.WZ_AKT.R" in self.vars:
            v = self.vars["V.G.WZ_AKT.R"]
            return v if isinstance(v, float) else 0.0
        if self.d_zero or self.tool_no is None:
            return 0.0
        return float(self.cfg.tool_radii.get(self.tool_no, 0.0))

    def check_trc_method(self, st: Step, g: Word, what: str) -> None:
        """G41/G42/G40 (word ``g``) under a selection method the simulator does not model: an error."""
        t = st.g.get(Group.TRC_SELECTION)
        code = 5 if t is not None else self.trc_method[0]
        if code in TRC_METHODS:
            raise self.error(st.block.line, g.col, f"G{g.raw} under G{code} ({TRC_METHODS[code]} of tool radius "
                             f"compensation): not modelled by the simulator; {what} with G139 (indirect, the default) "
                             "or G138 (direct)")

    def radius_comp(self, st: Step, g: Word) -> None:
        """G41/G42 select tool radius compensation from the next motion in the plane on; G40 deselects
        it with the next motion in the plane (TwinCAT CNC manual, "Tool radius compensation")."""
        code = int(g.value)
        line = st.block.line
        if code == 40:
            if self.comp_buf is not None:
                self.check_trc_method(st, g, "deselect it")
                self.comp_off = True
            return
        if self.comp_buf is not None:
            if code != self.comp:
                raise self.error(line, g.col, f"G{code} while G{self.comp} is active: a change of the compensation "
                                 "side without G40 is not modelled by the simulator (program G40 in between)")
            return
        if self.cfg.machine_kind == "lathe":
            raise self.error(line, g.col, f"G{code} (tool nose radius compensation on a lathe) is not modelled by the "
                             "simulator: program the tool tip path (G40)")
        self.check_trc_method(st, g, "select it")
        r = self.trc_radius()
        if r == 0:
            self.warn(st.src, f"G{code} with tool radius 0 (the setup gives no radius for the active tool, or D0): "
                      "the path is not offset")
        self.comp, self.comp_radius, self.comp_plane, self.comp_off = code, r, self.plane, False
        a, c, _ = PLANE_AXES[self.plane]
        L = self.turned_linear
        self.comp_flip = -1.0 if L[a][a] * L[c][c] - L[a][c] * L[c][a] < 0 else 1.0  # manual: mirroring swaps the side
        self.comp_buf = []

    def flush_comp(self, departure: bool) -> None:
        """The buffered records, offset to the tool centre path, go to the program."""
        buf, self.comp_buf = self.comp_buf, None
        side = (1.0 if self.comp == 41 else -1.0) * self.comp_flip
        self.comp, self.comp_off = 40, False

        def err(r, msg):
            return CutsimError(r.src.program, r.src.line, r.src.col, msg)
        recs = compensate_records(buf, side * self.comp_radius, self.comp_plane, departure,
                                  self.trc_method[0] == 138, self.trc_linear, err)
        self.program.records.extend(recs)
        for rec in reversed(recs):
            if isinstance(rec, canon.MOTIONS):
                self.moved(rec.end)
                break

    def convert_motion(self, st: Step) -> None:
        g = st.g.get(Group.RADIUS_COMP)
        if g is not None:
            self.radius_comp(st, g)
        if self.comp_buf is not None and self.plane != self.comp_plane:
            raise self.error(st.block.line, 1, f"plane changed to {self.plane} while tool radius compensation is active "
                             f"in {self.comp_plane}: not modelled by the simulator")
        before = tuple(self.pos)
        self.convert_path(st)
        if self.comp_off and self.comp_buf is not None:
            a, c, _ = PLANE_AXES[self.comp_plane]
            if self.pos[a] != before[a] or self.pos[c] != before[c]:
                self.flush_comp(departure=True)

    def convert_path(self, st: Step) -> None:
        b, src, words, motion = st.block, st.src, st.words, st.motion
        self.extra_axes(st)
        if self.turned and self.rotation is not None and self.rotation[1] != self.plane:
            self.rotation = None  # manual: a change of plane deselects the contour rotation, with a warning
            self.warn(src, "the change of plane deselects the contour rotation (#ROTATION)")
            self.frame_changed(b.line, 1)
        self.r_col = words["R"].col if "R" in words else 1  # errors of a modal R name this block's R, else the block
        if "R" in words:  # circle radius, modal (manual: "Radius programming (R, G163)")
            w = words.pop("R")
            if w.value == 0:
                raise self.error(b.line, w.col, "circle radius R must not be 0")
            self.circle_r = w.value
        axis_words = {AXES.index(a): words.pop(a) for a in AXES if a in words}
        values = {i: w.value for i, w in axis_words.items()}
        cols = {i: w.col for i, w in axis_words.items()}
        centre = {a: words.pop(a) for a in "IJK" if a in words}
        if self.motion == 33:
            if self.turned:
                raise self.error(b.line, 1, "G33 in rotated or mirrored coordinates is not modelled by the simulator")
            self.thread_block(b, src, centre, values, cols)
        elif self.motion in (2, 3) and (axis_words or motion in (2, 3)):
            self.circle(b, src, centre, values, cols)
        else:
            for a, w in centre.items():
                what = f"a G0{self.motion} block" if axis_words or motion is not None else "a block without a motion"
                raise self.error(b.line, w.col, f"address {a} has no meaning in {what}")
            if axis_words:
                end = self.target(values)
                self.check_position(b.line, end, cols)
                (self.rapid if self.motion == 0 else self.linear)(src, end)

    def convert_end(self, st: Step) -> None:
        """M05, the subprogram call, then the program or subprogram end; ``st.result`` is True when
        the block returns from a subprogram (or the program ended)."""
        b, src, fr = st.block, st.src, st.context
        if st.direction == 0:
            self.spindle(src, 0, None if st.speed is None else st.speed.value)
        implicit = st.result
        st.result = None
        if b.call is not None:
            self.call_local(b, fr)
        elif b.gcall is not None:
            self.call_global(b, fr)
        if implicit is not None and not self.ended:
            self.call_implicit(b, fr, implicit[1], implicit[2])
        if self.ended:
            st.result = True
            return
        ends = self.m_group(st, Group.END)
        if ends and self.M_CODES[ends[0][0]].meaning == "program end":
            self.end(src)
            self.ended = True
            st.result = True
        elif ends:
            if not fr.stack:  # a subprogram file run as the program: its end is the program's end
                self.warn(src, f"M{ends[0][1].raw} ends a subprogram: the program (run as a main program) ends here")
                self.end(src)
                self.ended = True
            st.result = True

    # -- subprogram calls --------------------------------------------------------------------------
    def enter(self, b: IsgBlock, col: int, target: str, fr: Frame) -> None:
        if target in fr.stack:
            raise self.error(b.line, col, f"recursive subprogram call: {' -> '.join(fr.stack + (target,))}")
        if len(fr.stack) >= MAX_CALL_DEPTH:
            s = fr.stack
            chain = " -> ".join(s[:3] + ("...",) + s[-2:] if len(s) > 6 else s)
            kind = "local subprograms" if b.call is not None else "subprograms"
            raise self.error(b.line, col, f"{'LL' if b.call is not None else 'L'} {target}: {kind} nested more than "
                             f"{MAX_CALL_DEPTH} deep "
                             f"({chain} -> {target}); the limit of open subprogram calls is {MAX_CALL_DEPTH}")

    def call_local(self, b: IsgBlock, fr: Frame, params: dict | None = None) -> None:
        """LL name (the caller's call parameters stay visible), LL CYCLE [NAME = name @P1 = ..] (its own,
        and the caller's modal state restored at its end); ``params``: a modal cycle called again."""
        target, col = b.call
        if params is None and b.modal:
            params = self.cycle_call(b, fr, "LL", target, col, b.cparams)
        sec = fr.local.get(target)
        if sec is None and self.external(b, target):
            return
        if sec is None:
            msg = f"unknown subprogram '{target}'"
            near = [n for n in fr.local if _folds(n) & _folds(target)]
            if near:
                msg += f"; did you mean '{near[0]}'?"
            elif fr.local:
                msg += f" (local subprograms here: {', '.join(sorted(fr.local))})"
            else:
                msg += " (this file defines no local subprogram '%L name')"
            raise self.error(b.line, col, msg)
        self.enter(b, col, target, fr)
        sub = Frame(fr.name, fr.local, fr.params if params is None else params, fr.stack + (target,),
                    fr.calls + ((fr.name, b.line),), cycle=params is not None)
        if params is None:
            self.run_level(sec, sub)
            return
        saved = self.cycle_state()
        self.run_level(sec, sub)
        self.restore_cycle_state(saved)

    def cycle_call(self, b: IsgBlock, fr: Frame, kind: str, name: str, col: int, pexprs: dict) -> dict:
        """A cycle call's checks and parameters; a MODAL_MOVE one becomes the level's modal cycle."""
        if fr.modal is not None:
            raise self.error(b.line, col, f"cycle call while the modal cycle {fr.modal[1]} (line {fr.modal[4]}) is "
                             "active: deselect it first with #DISABLE MODAL CYCLE")
        if b.modal == "MODAL_BLOCK":
            raise self.error(b.line, col, "MODAL_BLOCK (the cycle called again after every block) is not modelled by "
                             "the simulator; MODAL_MOVE (again after every block with a motion) is")
        params = {k: f(self) for k, f in pexprs.items()}
        if b.modal == "MODAL_MOVE":
            fr.modal = (kind, name, col, params, b.line)
        return params

    def run_level(self, sec: Section, sub: Frame) -> None:
        saved, saved_name = self.frame, self.name
        self.frame, self.name = sub, sub.name
        try:
            self.declare(sec)
            self.section(sec)
        finally:
            self.frame, self.name = saved, saved_name

    def call_global(self, b: IsgBlock, fr: Frame) -> None:
        fname, col, pexprs = b.gcall
        if b.modal:
            params = self.cycle_call(b, fr, "L", fname, col, pexprs)
        else:
            params = {k: f(self) for k, f in pexprs.items()}
        self.global_file(b, fr, fname, col, params, cycle=bool(b.modal))

    def modal_cycle(self, b: IsgBlock, fr: Frame) -> None:
        """The modal cycle (L CYCLE [NAME = .. MODAL_MOVE ..]) again after block ``b`` of its program
        level, which has a motion (manual: "Cycles as global or local subroutines")."""
        kind, name, col, params, _ = fr.modal
        if kind == "LL":
            self.call_local(IsgBlock(b.line, b.col, b.label, call=(name, col)), fr, dict(params))
        else:
            self.global_file(b, fr, name, col, dict(params), cycle=True)

    def global_file(self, b: IsgBlock, fr: Frame, fname: str, col: int, params: dict, cycle: bool) -> None:
        """Run the global subprogram file ``fname`` (a declared external one: nothing); a cycle restores
        the caller's modal state when it ends."""
        path = self.find_file(fname, b.line, col, missing_ok=True)
        if path is None:
            if self.external(b, fname):
                return
            self.find_file(fname, b.line, col)  # the error naming the folders and the setup keys
        if not cycle:
            self.run_file(b, fr, path, fname, col, params)
            return
        saved = self.cycle_state()
        self.run_file(b, fr, path, fname, col, params, cycle=True)
        self.restore_cycle_state(saved)

    _CYCLE_STATE = ("motion", "absolute", "per_rev", "feed", "plane", "circle_r", "centre_abs")

    def cycle_state(self) -> tuple:
        """The modal G functions, circle data and feed a cycle restores when it ends (manual: P-CHAN-00210
        cycle_changes_modal, default 0)."""
        return tuple(getattr(self, k) for k in self._CYCLE_STATE)

    def restore_cycle_state(self, saved: tuple) -> None:
        if self.ended:
            return
        for k, v in zip(self._CYCLE_STATE, saved):
            setattr(self, k, v)

    def external(self, b: IsgBlock, fname: str) -> bool:
        """A subprogram, cycle file or implicit-call G code the setup declares the machine has
        (``[machine] external_subprograms``) and the simulator does not: True (after one warning per
        name) when ``fname`` is one of them; nothing runs and the tool stays where it is."""
        base = fname.replace("\\", "/").rsplit("/", 1)[-1]
        stem = os.path.splitext(base.upper())[0] or base.upper()
        if stem not in self.external_stems:
            return False
        if self.external_skipped is None:
            self.external_skipped = base
        self.warn_once(("external", stem), Src(self.name, b.line, 1, b.label, self.frame.calls),
                       f"{base} is declared external in the setup ([machine] external_subprograms): its motion is not "
                       "simulated, the tool is taken to stay where it was")
        return True

    def run_file(self, b: IsgBlock, fr: Frame, path: str, fname: str, col: int, params: dict,
                 cycle: bool = False) -> None:
        if path not in self.files:
            text = self.read_file(path, fname, b.line, col)
            self.files[path] = parse(path, text, self.cfg.max_blocks, self.macros, isg_fast.read_plain)
        main, local = self.files[path]
        label = os.path.basename(path)
        self.enter(b, col, label, fr)
        sub = Frame(path, local, params, fr.stack + (label,), fr.calls + ((fr.name, b.line),), cycle)
        self.run_level(main, sub)

    def call_implicit(self, b: IsgBlock, fr: Frame, code: int, g: Word) -> None:
        """G80..G89 and G800..G819 call a subprogram the machine maker configures; the simulator runs
        the file G<n>.nc from the program's folder or [machine] subprogram_path, the values of an
        argument list G805[a, b, c] as @P1, @P2, @P3 (assumption, docs/dialects/isg.md)."""
        args = [f(self) for f in b.args.get(g.col, [])]
        name = self.implicit_files.get(f"G{code}", f"G{code}")
        path = self.find_file(name, b.line, g.col, missing_ok=True)
        if path is None:
            if self.external(b, name) or self.external(b, f"G{code}"):
                return
            raise self.error(b.line, g.col, f"G{g.raw} is an implicit subroutine call: the machine maker's "
                             f"subprogram behind it ({name}) is not known to the simulator (put the file in the "
                             "program's folder or in the setup's [machine] subprogram_path, or declare it in the "
                             f"setup: [machine] external_subprograms = [\"{name}\"])")
        params = {f"@P{k + 1}": v for k, v in enumerate(args)}
        saved = self.cycle_state()
        self.run_file(b, fr, path, name, g.col, params, cycle=g.col in b.args)
        if g.col in b.args:  # with transfer parameters the call is a cycle call (manual): its changes end with it
            self.restore_cycle_state(saved)

    def g80_plain(self, g: Word, b: IsgBlock) -> bool:
        """G80 without an argument list, with no file named for it (#FILE NAME, G80.nc on the search
        path) and not declared external: the ISO "modal cycle off", which moves nothing."""
        if "G80" in self.implicit_files or g.col in b.args or "G80" in self.external_stems:
            return False
        return self.find_file("G80", b.line, g.col, missing_ok=True) is None

    def find_file(self, fname: str, line: int, col: int, missing_ok: bool = False) -> str | None:
        """A global subprogram: the program's folder, then [machine] subprogram_path. A path written
        for the controller (C:\\...\\name.nc) is looked up by its file name; names compare without
        case, with or without ``.nc``."""
        base = fname.replace("\\", "/").rsplit("/", 1)[-1]
        dirs = [os.path.dirname(os.path.abspath(self.name)), *self.cfg.subprogram_path]
        path = find_subprogram(base, dirs, SUB_EXTENSIONS)
        if path is not None or missing_ok:
            return path
        alt = "" if base.upper().endswith(".NC") else f" (or {base}.nc)"
        raise self.error(line, col, f"global subprogram '{fname}': no file {base}{alt} in "
                         f"{' or '.join(dirs)} (give its folder in the setup: [machine] subprogram_path, or, when the "
                         f"machine has it and its motion need not be simulated: [machine] external_subprograms = "
                         f"[\"{base}\"]; a local subprogram of this file is defined as '%L name' and called with "
                         "'LL name')")

    def read_file(self, path: str, fname: str, line: int, col: int) -> str:
        what = f"subprogram {fname}: {path}"
        try:
            data = read_bounded(path, MAX_SUB_BYTES)
        except Unreadable as e:
            if e.kind == "directory":
                raise self.error(line, col, f"{what} is a directory, not a program file") from None
            if e.kind == "special":
                raise self.error(line, col, f"{what} is not a regular file") from None
            if e.kind == "large":
                size = f"{e.size:,}" if e.size >= 0 else "more"
                raise self.error(line, col, f"{what} has {size} bytes, more than the {MAX_SUB_BYTES:,} a "
                                 "subprogram file may have") from None
            raise self.error(line, col, f"{what} cannot be read ({e.reason})") from None
        return data.decode("utf-8-sig", errors="replace")

    # -- G33 -------------------------------------------------------------------------------------
    def thread_block(self, b: IsgBlock, src: Src, leads: dict[str, Word], values: dict[int, float],
                     cols: dict[int, int]) -> None:
        if len(leads) > 1:
            a, w = list(leads.items())[1]
            raise self.error(b.line, w.col, f"two leads ({' and '.join(leads)}) in one G33 block: "
                             "program the lead on one of I, J, K")
        for a, w in leads.items():
            if w.raw.lstrip("+").startswith(("-", "\u2212")):
                raise self.error(b.line, w.col, f"the lead {a}{w.raw} is programmed without a sign")
            if w.value == 0:
                raise self.error(b.line, w.col, f"the lead {a}{w.raw} must not be zero when G33 is selected")
            if w.value < MIN_LEAD:
                raise self.error(b.line, w.col, f"the lead {a}{w.raw} is below the programming resolution, "
                                 f"{MIN_LEAD} mm per revolution")
            self.lead = (w.value, LEADS[a])
        if self.lead is None:
            col = b.words[0].col if b.words else 1
            for w in b.words:
                if w.letter == "G" and w.value == 33:
                    col = w.col
            raise self.error(b.line, col, "G33 without a lead: program it without sign on I, J or K "
                             "(mm per revolution along X, Y or Z), e.g. 'G33 Z48 K1.5'")
        if not values:
            return
        end = self.target(values)
        self.check_position(b.line, end, cols)
        lead, axis = self.lead
        self.synced(src, end, lead, axis, self.offset)

    # -- circles ---------------------------------------------------------------------------------
    def circle(self, b: IsgBlock, src: Src, words: dict[str, Word], values: dict[int, float],
               cols: dict[int, int]) -> None:
        if self.turned:
            return self.turned_circle(b, src, words, values, cols)
        if self.centre_abs:  # G161: I/J/K are absolute centre coordinates -> relative to the start
            sh = self.shift()
            words = {a: Word(a, w.value + sh["IJK".index(a)] - self.pos["IJK".index(a)], w.raw, w.col)
                     for a, w in words.items()}
            if self.diameter and "I" in words:
                w = words["I"]
                words["I"] = Word("I", w.value / 2.0, w.raw, w.col)
        end = self.target(values)
        self.check_position(b.line, end, cols)
        a, c, _ = PLANE_AXES[self.plane]
        if not words and self.circle_r is not None:
            centre = self.radius_centre(b.line, end, self.motion == 2)
        else:
            centre = self.centre_words(b.line, words, ", relative to the start; or its radius R")
        self.arc(src, end, centre, self.motion == 2)

    def turned_circle(self, b: IsgBlock, src: Src, words: dict[str, Word], values: dict[int, float],
                      cols: dict[int, int]) -> None:
        """A circle in rotated or mirrored coordinates: its centre offsets turn with the frame; a mirrored
        plane reverses its direction (G02 <-> G03). The plane must map onto itself."""
        f = self.program_frame()
        L = f.L
        a, c, n = PLANE_AXES[self.plane]
        if abs(abs(L[n][n]) - 1.0) > 1e-12:
            raise self.error(b.line, 1, f"a circle in the plane {self.plane} under a coordinate system rotated about Z "
                             "lies in a tilted plane: not modelled by the simulator (program it in G17)")
        if self.centre_abs:  # G161: absolute centre coordinates of the program frame -> relative to the start
            p = f.inverse_apply(self.pos)
            words = {k: Word(k, w.value - p["IJK".index(k)], w.raw, w.col) for k, w in words.items()}
        end = self.target(values)
        self.check_position(b.line, end, cols)
        cw = self.motion == 2
        if f.plane_flips(a, c):
            cw = not cw
        if not words and self.circle_r is not None:
            centre = self.radius_centre(b.line, end, cw)
        else:
            prog_centre = self.centre_words(b.line, words, ", relative to the start; or its radius R")
            d = f.linear(tuple(prog_centre[i] - self.pos[i] for i in range(3)))
            centre = (self.pos[0] + d[0], self.pos[1] + d[1], self.pos[2] + d[2])
        self.arc(src, end, centre, cw)

    def radius_centre(self, line: int, end, cw: bool):
        """The centre of a circle given by its radius R (modal): the shorter arc for R > 0, the
        longer one for R < 0 (manual: "Radius programming (R, G163)"); the chord in the plane."""
        r, col = self.circle_r, self.r_col
        try:
            return radius_centre(self.pos, end, r, self.plane, cw, self.diameter)
        except FullCircle:
            raise self.error(line, col, "a full circle cannot be programmed with its radius R (start and end point "
                             "coincide): program its centre with I, J, K") from None
        except RadiusTooSmall as e:
            raise self.error(line, col, f"circle radius R{abs(r):g} is too small for the distance {e.chord:.4f} between "
                             "the start and the end point") from None


def _element_keys(name: str, dims: tuple) -> list[str]:
    if not dims:
        return [name]
    keys = [name]
    for d in dims:
        keys = [f"{k}[{i}]" for k in keys for i in range(d)]
    return keys


_AXIS_LETTERS = frozenset("XYZABCUVW")
_NO_MOTION_G = frozenset({4.0, 92.0, 98.0, 99.0, 130.0, 132.0, 230.0, 333.0})  # G codes whose axis words are not a motion


def _moves(b: IsgBlock) -> bool:
    """The block holds motion commands (axis words) - what calls a MODAL_MOVE cycle again."""
    letters = {w.letter for w in b.words} | {it[1] for it in b.items if it[0] == "x"}
    if not letters & _AXIS_LETTERS:
        return False
    return not any(w.letter == "G" and w.value in _NO_MOTION_G for w in b.words)


def _ends_program(b: IsgBlock) -> bool:
    return any(w.letter == "M" and w.value in (2, 30) for w in b.words)


def _ends_sub(b: IsgBlock) -> bool:
    return any(w.letter == "M" and w.value in (17, 29) for w in b.words)


def static_counts(main: Section, local: dict[str, Section]) -> dict | None:
    """Blocks each body executes, its calls included, without running it (only for bodies without
    control flow): name (None for the main program) -> (count, whether it ends the program). None
    when a call names an unknown subprogram or is recursive (errors when they run)."""
    counts: dict = {}
    bodies = {None: main, **local}
    stack = [[None, 0, 0]]
    open_names = {None}
    while stack:
        frame = stack[-1]
        name, k, total = frame
        blocks = bodies[name].blocks
        pushed = False
        ended = False
        while k < len(blocks):
            b = blocks[k]
            callee = b.call[0] if b.call is not None else None
            if callee is not None:
                if callee not in local or callee in open_names:
                    return None
                if callee not in counts:
                    frame[1], frame[2] = k, total
                    stack.append([callee, 0, 0])
                    open_names.add(callee)
                    pushed = True
                    break
            total += 1 + (counts[callee][0] if callee is not None else 0)
            k += 1
            if _ends_program(b) or (callee is not None and counts[callee][1]):
                ended = True
                break
            if name is not None and _ends_sub(b):
                break
        if pushed:
            continue
        counts[name] = (total, ended)
        stack.pop()
        open_names.discard(name)
    return counts


def interpret(name: str, text: str, cfg: InterpConfig) -> canon.Program:
    return Isg(name, cfg).run(text)
