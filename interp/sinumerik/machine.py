"""Sinumerik machine-side semantics: units, frames, extra axes, tools, spindles and machine functions
(docs/dialects/sinumerik.md, "Units, frames and axes").

Pure interpreter logic: the Sinumerik interpreter (interp/sinumerik/interpreter.py) keeps its position
``m.pos`` in **machine coordinates in mm** (what the canonical records carry); the program speaks
in the **workpiece coordinate system** (WCS) of the active frames and units. The chain, applied to
every programmed point (end points, arc centres, cycle moves)::

    machine = settable offset (G54.., from the setup) + programmable frame (TRANS/ROT/SCALE/MIRROR,
              an affine map) applied to (the programmed value x 25.4 under G70/G700)

G53 and SUPA suppress both offsets for their block. A point that is not programmed keeps its WCS
value (so a changed offset moves only the axes a block names, as on the control).

The interpreter calls in through one small hook in each of its ``word``, ``check_g`` (``g_codes``),
``settings``, ``move``, ``change_tool`` (and reads ``arc_flip``). Imports flow one way: this module
imports only codes, syntax and frames below it; the interpreter hands in what it needs from above
(the cycle names to ``settings``, ``run_cycle`` to ``move``).
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field, replace

from .. import canon
from ..errors import CutsimError
from ..core.modal import PLANE_AXES, InterpConfig
from ..core.frames import Affine, cofactor, IDENTITY, mat_mul, Mat, ZERO
from .frames import _diag, _rot
from ..core import CENTRE_WORDS, Group
from .codes import G_CODES, M_CODES, PATH_ONLY
from . import lathe
from .syntax import COORD_LIMIT, range_message

INCH = 25.4
AXES = "XYZ"
ROTARY_LETTERS = "ABC"
AXIS_NAME = re.compile(r"[A-Z][0-9]*")  # an axis address: A, B, W, X2 (AX[X2]=..)
# the addresses the language itself means (X Y Z are the machine's own axes); any other single letter
# (with a number) in an address is an axis, which the setup must declare
LANGUAGE_ADDRESSES = {"G", "M", "X", "Y", "Z", "I", "J", "K", "F", "S", "T", "D", "L", "P", "N", "R", "H", "E", "Q"}
FRAME_CMDS = {"TRANS", "ATRANS", "ROT", "AROT", "SCALE", "ASCALE", "MIRROR", "AMIRROR"}
# commands that do not change the programmed tool path (what they do on the machine)
ACCEPTED = {
    "CUT2D": "2D radius compensation (the default)", "CUT2DF": "2D radius compensation in the frame plane",
    "CDON": "bottleneck detection on", "CDOF": "bottleneck detection off", "CDOF2": "bottleneck detection off",
    "ORIWKS": "orientation in the workpiece system", "ORIMKS": "orientation in the machine system",
    "ORIAXES": "orientation by axis interpolation", "ORIVECT": "orientation by vector interpolation",
    "PAROTOF": "workpiece-aligned rotation off", "TOROTOF": "tool-aligned rotation off",
    "DYNNORM": "standard dynamics", "DYNPOS": "positioning dynamics", "DYNROUGH": "roughing dynamics",
    "DYNSEMIFIN": "semi-finishing dynamics", "DYNFINISH": "finishing dynamics",
    "FGREF": "reference radius for rotary-axis feed",
    "NORM": "radius compensation approaches straight (the simulator's only way)",
    "COMPOF": "compressor off", "COMPON": "compressor on", "COMPCURV": "compressor (curvature)",
    "COMPCAD": "compressor (CAD)", "DRFOF": "handwheel offsets off", "FFWON": "feed forward on",
    "FFWOF": "feed forward off", "SOFT": "jerk-limited acceleration", "BRISK": "step acceleration",
    "SOFTA": "jerk-limited acceleration", "BRISKA": "step acceleration", "CFC": "constant feed at the contour",
    "CFTCP": "constant feed at the tool centre", "CFIN": "constant feed on inner arcs",
    "UPATH": "path parameter", "SPATH": "path parameter", "FGROUP": "feed group of axes",
    "CYCLE832": "high-speed settings",
}
CALL_ACCEPTED = {"CYCLE832"}
EPS = 1e-9
SCALE_MIN, SCALE_MAX = 1e-6, 1e6  # what SCALE/ASCALE may make of an axis in all
FRAME_SHIFT_MAX = 1e7  # mm: the programmable frame's total shift (positions are checked against COORD_LIMIT anyway)
# interp/drilling.run_modal runs the modal cycle through ``in_wcs``; set False, a modal cycle
# after a move under a frame would be an error (its holes would land in the wrong place)
MODAL_CYCLES_IN_WCS = True

@dataclass
class Word:
    """An address value this module puts into the block (an extra axis, a tool number from a name):
    the same fields as the interpreter's own Value."""
    value: float
    mode: str | None
    col: int


@dataclass
class Modal:
    """The modal part of the machine state, which PROC ... SAVE puts back on return: it lives on the
    interpreter as ``m.machine_modal`` (named in interp/sinumerik/interpreter.py's SAVED_MODAL), so that the
    interpreter's save_modal/restore_modal copy and restore it with its own G groups."""
    inch: bool = False  # G70/G700: geometry in inch
    inch_feed: bool = False  # G700: F in inch/min (inch/rev)
    settable: str = "G500"
    offset: tuple[float, float, float] = ZERO
    frame: Affine = field(default_factory=Affine)  # programmable frame
    diam: str = "DIAMOF"  # the lathe's diameter mode: DIAMON, DIAMOF, DIAM90, DIAMCYCOF (lathe.py)


def _modal(name: str) -> property:
    return property(lambda self: getattr(self.m.machine_modal, name),
                    lambda self, v: setattr(self.m.machine_modal, name, v))


@dataclass
class Machine:
    """The machine-side state of one run (its modal part in ``m.machine_modal``)."""
    cfg: InterpConfig
    m: object = None  # the interpreter
    inch = _modal("inch")
    inch_feed = _modal("inch_feed")
    settable = _modal("settable")
    offset = _modal("offset")
    frame = _modal("frame")
    suppress: bool = False  # G53/G153/SUPA in this block
    axis_pos: dict[str, float] = field(default_factory=dict)
    warned: set = field(default_factory=set)
    pending: list = field(default_factory=list)  # warnings of the block waiting for its Src
    master: int = 1  # SETMS
    speed_min: float = 0.0  # G25 S.. (rpm), 0: none
    speed_max: float = 0.0  # G26 S.. (rpm), 0: none
    traori: bool = False
    arc_flip: bool = False  # the arc being programmed turns the other way in the machine (mirror)
    sandbox: bool = False  # a cycle runs in WCS; its records are mapped afterwards
    deferred: list = field(default_factory=list)  # cycles of the block under a frame, run by ``move``
    lathe: lathe.Lathe = field(default_factory=lathe.Lathe)  # threads, tapping, G96 (interp/sinumerik/lathe.py)

    # -- the transform -----------------------------------------------------------------------------
    def unit(self) -> float:
        return INCH if self.inch else 1.0

    def linear_part(self) -> Mat:
        u = self.unit()
        a = IDENTITY if self.suppress else self.frame.L
        return tuple(tuple(v * u for v in r) for r in a)  # type: ignore

    def identity(self) -> bool:
        return not self.inch and (self.suppress or (self.frame.identity() and self.offset == ZERO))

    def to_machine(self, p) -> tuple[float, float, float]:
        """A WCS point in mm (program units already x 25.4) -> machine mm."""
        if self.suppress:
            return (p[0], p[1], p[2])
        q = self.frame.linear(p)
        t, o = self.frame.t, self.offset
        return (q[0] + t[0] + o[0], q[1] + t[1] + o[1], q[2] + t[2] + o[2])

    def to_wcs(self, p) -> tuple[float, float, float]:
        """Machine mm -> WCS mm (the inverse of ``to_machine``)."""
        if self.suppress:
            return (p[0], p[1], p[2])
        t, o = self.frame.t, self.offset
        d = (p[0] - t[0] - o[0], p[1] - t[1] - o[1], p[2] - t[2] - o[2])
        return self.frame.inverse_linear(d)

    def warn_once(self, m, src, key: str, message: str) -> None:
        if key in self.warned:
            return
        self.warned.add(key)
        if src is None:
            self.pending.append(message)
        else:
            m.warn(src, message)

    def axis_value(self, m, name: str) -> float | None:
        """The position of axis ``name`` in the program's terms: X/Y/Z in the WCS and the active
        unit, an extra axis as tracked (degrees for a rotary axis); None for an axis the machine
        does not have. (For $AA_IW[..], AX[..] and AXIS variables.)"""
        name = name.upper()
        if name in AXES:
            return self.to_wcs(m.pos)[AXES.index(name)] / self.unit()
        if name in self.cfg.axes:
            return self.axis_pos.get(name, 0.0)
        return None


def axis_message(name: str) -> str:
    kind = "rotary" if name[:1] in ROTARY_LETTERS else "linear"
    return f"axis {name} is not on this machine (declare it in the setup: [machine] axes = {{ {name} = \"{kind}\" }})"


# -- hook: word (a block's addresses, before the interpreter's own checks) ---------------------------
def word(m, st, val, line: int, blk) -> bool:
    """Addresses this module owns: M codes beyond the table (the setup's machine M functions),
    extra axes, ``T="name"``, spindle addresses ``M1=3``/``S1=1000``, ``SPOS``, ``RPL``. True when
    the word is taken care of."""
    ms = m.machine
    addr = st.address.upper()
    ext = getattr(st, "ext", None)
    if ext is not None and addr in ("M", "S"):  # M1=3, S1=1000: spindle 1
        return spindle_address(m, ms, addr, ext, val, line, st.col, blk)
    if ext is not None and addr == "T":  # T1=5, T2="PARTOFF": the tool for spindle n
        return spindle_tool(m, ms, ext, val, line, st.col, blk)
    if addr == "M" and not isinstance(val, str):
        return m_code(m, val, st.col, line, blk)
    if addr == "T" and isinstance(val, str):
        if "T" in blk.words:
            raise m.error(line, st.col, "address T appears twice in one block")
        blk.words["T"] = Word(float(tool_number(m, val, line, st.col)), None, st.col)
        return True
    if addr in m.cfg.axes or addr not in LANGUAGE_ADDRESSES and AXIS_NAME.fullmatch(addr):
        if addr not in m.cfg.axes:
            raise m.error(line, st.col, axis_message(addr))
        if addr in blk.words:
            raise m.error(line, st.col, f"address {addr} appears twice in one block")
        v = m.num(val, line, st.col)
        if abs(v) > COORD_LIMIT:
            raise m.error(line, st.col, range_message(addr, v, -COORD_LIMIT, COORD_LIMIT, "mm or degrees"))
        blk.words[addr] = Word(v, st.mode, st.col)
        return True
    if addr == "RPL":
        blk.words["RPL"] = Word(m.num(val, line, st.col), None, st.col)
        return True
    if addr == "SPOS":  # spindle positioning: the angle a lathe's G331 starts at
        return lathe.position_spindle(m, ms, m.num(val, line, st.col), getattr(st, "mode", None))
    if addr in lathe.LATHE_WORDS:  # SF= DITS= DITE= LIMS=: lathe.settings applies them
        if addr in blk.words:
            raise m.error(line, st.col, f"address {addr} appears twice in one block")
        blk.words[addr] = Word(m.num(val, line, st.col), None, st.col)
        return True
    return False


def m_code(m, val: float, col: int, line: int, blk) -> bool:
    """An M code outside the table (codes.M_CODES): a machine function the setup declares passes;
    any other is an error. False for the table's codes (and a value that is not whole)."""
    if val != int(val) or int(val) in M_CODES:
        return False
    code = int(val)
    if code in m.cfg.m_functions:
        return True
    raise m.error(line, col, f"M{code} is not known to the simulator (a machine M function: declare it in the setup: "
                  f"[machine] m_functions = [{code}])")


def spindle_tool(m, ms: Machine, n: int, val, line: int, col: int, blk) -> bool:
    """T<n>=<number or name>: the tool for spindle n (the address extension is the spindle's number,
    FUN "Tool change with T command"). The master spindle's is a T word; another spindle's warns
    once and changes nothing (the simulation follows the master spindle only)."""
    if n != ms.master:
        ms.warn_once(m, None, f"tool{n}", f"T{n}=: a tool for spindle {n}, which is not the master spindle; the "
                     "simulation follows the master spindle only (the tool in use stays)")
        return True
    if "T" in blk.words:
        raise m.error(line, col, "address T appears twice in one block")
    number = tool_number(m, val, line, col) if isinstance(val, str) else m.num(val, line, col)
    blk.words["T"] = Word(float(number), None, col)
    return True


def spindle_address(m, ms: Machine, letter: str, n: int, val, line: int, col: int, blk) -> bool:
    v = m.num(val, line, col)
    if n != ms.master:
        ms.warn_once(m, None, f"spindle{n}", f"{letter}{n}=: spindle {n} is not the master spindle; the simulation "
                     "follows the master spindle only")
        return True
    if letter == "S":
        if "S" in blk.words:
            raise m.error(line, col, "the spindle speed appears twice in one block")
        blk.words["S"] = Word(v, None, col)
        return True
    if v != int(v):
        raise m.error(line, col, f"M{n}={v:g}: an M function is a whole number")
    code = int(v)
    if code in (3, 4, 5):
        blk.ms.append((code, col))
        return True
    row = M_CODES.get(code)
    if (row is not None and row.group in (Group.SPINDLE, Group.GEAR)) or code in m.cfg.m_functions:
        return True  # spindle positioning, gear stages, the setup's machine functions: no path effect
    raise m.error(line, col, f"M{n}={code} is not a spindle function the simulator knows (M{n}=3, 4, 5, 19, 40 to 45; a "
                  f"machine function: declare it in the setup: [machine] m_functions = [{code}])")


def tool_number(m, name: str, line: int, col: int) -> int:
    names = m.cfg.tool_names
    if name in names:
        return names[name]
    for k, v in names.items():
        if k.upper() == name.upper():
            return v
    raise m.error(line, col, f"tool \"{name}\" is not in the setup (give the tool its name: [[tool]] name = \"{name}\")")


# -- hook: check_g (the block's G codes, before the interpreter applies its own) ----------------------
def g_codes(m, gs: list[tuple[int, int]], line: int) -> list[tuple[int, int]]:
    """Apply units, settable frames, G53 and the path-mode codes (codes.G_CODES); the rest is
    returned for the interpreter (G41/G42 swapped while a mirror turns the plane over)."""
    ms = m.machine
    ms.suppress = False
    ms.lathe.g63 = False
    rest = []
    seen: dict[Group, tuple[int, int]] = {}
    for code, col in gs:
        group = G_CODES[code].group
        if group is Group.UNITS or group is Group.ZERO_OFFSET:
            if group in seen:
                raise m.error(line, col, f"G{code} conflicts with G{seen[group][0]} in the same block")
            seen[group] = (code, col)
        if group is Group.UNITS:
            ms.inch, ms.inch_feed = code in (70, 700), code == 700
        elif code == 500:
            ms.settable = "G500"
            ms.offset = tuple(map(float, m.cfg.work_offsets.get("G500", ZERO)))  # type: ignore
        elif group is Group.ZERO_OFFSET:
            settable(m, ms, f"G{code}")
        elif code in (53, 153):
            suppress(m, ms, f"G{code}")
        elif code in PATH_ONLY:
            ms.warn_once(m, None, f"G{code}", f"G{code} ({G_CODES[code].meaning}) does not change the tool path; "
                         "accepted")
        elif code in lathe.SYNCED or code == 63:
            if not lathe.is_lathe(m):
                raise m.error(line, col, f"G{code} ({G_CODES[code].meaning}) needs a lathe: the setup's machine is a "
                              "mill ([machine] kind = \"lathe\")")
            if code == 63:
                ms.lathe.g63 = True
            else:
                rest.append((code, col))
        elif group is Group.SPINDLE_MODE:
            if code in (961, 971):
                m.per_rev = False  # G961/G971: the feed in mm/min, as G94
            if lathe.is_lathe(m):
                lathe.spindle_mode(m, ms, code, canon.Src(m.unit_program, line, col))
            elif code in (96, 961):
                ms.warn_once(m, None, f"G{code}", f"G{code} ({G_CODES[code].meaning}): S is a cutting speed in "
                             "m/min; the tool path is unchanged, the spindle speed is recorded as written (not in rpm)")
        elif code in (41, 42) and flipped(ms, m.plane):
            rest.append((83 - code, col))
        else:
            rest.append((code, col))
    return rest


def settable(m, ms: Machine, key: str) -> None:
    """G54 .. G57, G505 .. G599: the setup's work offset of that name (0 with one warning without)."""
    ms.settable = key
    if key in m.cfg.work_offsets:
        ms.offset = tuple(map(float, m.cfg.work_offsets[key]))  # type: ignore
    else:
        ms.offset = ZERO
        ms.warn_once(m, None, key, f"{key}: no work offset in the setup, offset 0 (declare it: "
                     f"[work_offsets] {key} = [x, y, z])")


def suppress(m, ms: Machine, what: str) -> None:
    """G53/G153/SUPA: this block's values are machine coordinates. Where the setup does not say
    where the workpiece sits in the machine, they are workpiece coordinates too (one warning)."""
    ms.suppress = True
    offsets = m.cfg.work_offsets
    if ms.settable not in offsets and (ms.settable != "G500" or not offsets):
        ms.warn_once(m, None, "machine-coordinates", f"{what}: machine coordinates are taken as workpiece coordinates "
                     f"(the setup does not place the workpiece: [work_offsets] {'G54' if ms.settable == 'G500' else ms.settable}"
                     " = [x, y, z])")


def flipped(ms: Machine, plane: str) -> bool:
    """True when the frame turns the plane over (an odd number of mirrors): G2 <-> G3, G41 <-> G42."""
    n = PLANE_AXES[plane][2]
    return cofactor(ms.linear_part())[n][n] < 0


# -- hook: settings (frames, accepted commands, cycles under a frame, feed units) --------------------
def settings(m, src, blk, cycles: set) -> None:
    """The block's machine keywords (``blk.commands``: frames, SUPA, TRAORI, the commands that do not
    change the tool path), CYCLE800/CYCLE832, F under G700, and cycles called under a frame
    (``cycles``: the names of the cycles, milling.CYCLES)."""
    ms = m.machine
    for msg in ms.pending:
        m.warn(src, msg)
    ms.pending.clear()
    line = src.line
    left = []
    frame_cmd = None
    for name, col in blk.commands:
        if name in FRAME_CMDS:
            if frame_cmd is not None:
                raise m.error(line, col, f"{frame_cmd[0]} and {name} in one block: write each frame "
                              "instruction in a block of its own")
            frame_cmd = (name, col)
        elif name == "SUPA":
            suppress(m, ms, "SUPA")
        elif name == "G500":
            ms.settable = "G500"
            ms.offset = tuple(map(float, m.cfg.work_offsets.get("G500", ZERO)))  # type: ignore
        elif name == "TRAORI":
            traori_on(m, ms, src, col)
        elif name == "TRAFOOF":
            ms.traori = False
        elif name in lathe.DIAMETER_MODES:
            lathe.diameter_command(m, ms, name, src, col)
        elif name in ACCEPTED:
            ms.warn_once(m, src, name, f"{name} ({ACCEPTED[name]}) does not change the tool path; accepted")
        else:
            left.append((name, col))
    blk.commands[:] = left
    for msg in ms.pending:  # SUPA's
        m.warn(src, msg)
    ms.pending.clear()
    keep = []
    for stmt in blk.calls:
        name, args = getattr(stmt, "name", None), getattr(stmt, "args", None)
        if name == "CYCLE800" and args is not None:
            cycle800(m, ms, src, stmt)
        elif name == "TRAORI" and args is not None:
            traori_on(m, ms, src, stmt.col)
        elif name in CALL_ACCEPTED and args is not None:
            ms.warn_once(m, src, name, f"{name} ({ACCEPTED[name]}) does not change the tool path; accepted")
        else:
            keep.append(stmt)
    blk.calls[:] = keep
    if frame_cmd is not None:
        frame(m, ms, frame_cmd[0], blk.words, line, frame_cmd[1])
    lathe.settings(m, ms, src, blk)
    if "F" in blk.words and ms.inch_feed:
        f = blk.words["F"]
        f.value *= INCH
    if not ms.identity() and not ms.sandbox:
        cycles_in_frame(m, ms, src, blk, cycles)


def traori_on(m, ms: Machine, src, col: int) -> None:
    turned = [a for a, v in sorted(ms.axis_pos.items()) if m.cfg.axes.get(a) == "rotary" and abs(v) > EPS]
    if turned:
        raise m.error(src.line, col, f"TRAORI with rotary axis {turned[0]} at {ms.axis_pos[turned[0]]:g} degrees: "
                      "a tilted tool (5-axis transformation) is not modelled in a 3-axis simulation")
    ms.traori = True
    ms.warn_once(m, src, "TRAORI", "TRAORI (5-axis transformation): the tool stays along Z in this 3-axis "
                 "simulation; a rotary axis move under TRAORI is an error")


CYCLE800_ROT = (7, 8, 9)  # _A, _B, _C (0-based positions in CYCLE800(_FR,_TC,_ST,_MODE,_X0,_Y0,_Z0,_A,_B,_C,...))
CYCLE800_OFF = (4, 5, 6, 10, 11, 12)  # _X0 _Y0 _Z0 _X1 _Y1 _Z1


def cycle800(m, ms: Machine, src, stmt) -> None:
    """CYCLE800 swivels the plane: with every rotation and offset 0 (the swivel reset CAM posts write
    before each operation) it changes nothing; a real swivel is not modelled."""
    line = src.line
    for k in CYCLE800_ROT + CYCLE800_OFF:
        if k < len(stmt.args) and stmt.args[k].value is not None:
            a = stmt.args[k]
            v = m.ev(a.value, line, a.col)
            if isinstance(v, str):
                raise m.error(line, a.col, f"CYCLE800: parameter {k + 1} must be a number, not the string \"{v}\"")
            if abs(v) > EPS:
                what = "a swivel (rotation)" if k in CYCLE800_ROT else "a swivel offset"
                raise m.error(line, a.col, f"CYCLE800: {what} of {v:g} is not modelled in a 3-axis simulation "
                              "(only CYCLE800 with every rotation and offset 0 is accepted)")
    ms.warn_once(m, src, "CYCLE800", "CYCLE800 with no rotation and no offset (swivel reset): no effect on the tool path")


def frame(m, ms: Machine, name: str, words: dict, line: int, col: int) -> None:
    """TRANS/ROT/SCALE/MIRROR replace the programmable frame, the A... forms add to it (in the
    coordinates of the frame so far); TRANS (ROT, ...) alone clears it."""
    vals = {}
    for a in ("X", "Y", "Z", "RPL"):
        if a in words:
            w = words.pop(a)
            if w.mode is not None:
                raise m.error(line, w.col, f"{name} takes plain values, not {a}=AC(..)/IC(..)")
            vals[a] = (w.value, w.col)
    for a in list(words):
        if a not in ("F", "S", "T", "D"):
            raise m.error(line, words[a].col, f"address {a} has no meaning in a {name} block")
    additive = name.startswith("A")
    base = name[1:] if additive else name
    u = ms.unit()
    if base == "TRANS":
        step = Affine(IDENTITY, tuple(vals.get(a, (0.0, 0))[0] * u for a in AXES))  # type: ignore
    elif base == "ROT":
        step = Affine(rotation(m, ms, vals, name, line, col), ZERO)
    elif base == "SCALE":
        if "RPL" in vals:
            raise m.error(line, vals["RPL"][1], f"RPL has no meaning in a {name} block")
        f = []
        for a in AXES:
            v, c = vals.get(a, (1.0, col))
            if abs(v) < 1e-6:
                raise m.error(line, c, f"{name} {a}{v:g}: a scale factor must not be 0")
            if v < 0:
                raise m.error(line, c, f"{name} {a}{v:g}: a negative scale factor mirrors; write MIRROR {a}0")
            f.append(v)
        step = Affine(_diag(*f), ZERO)
    else:  # MIRROR
        if "RPL" in vals:
            raise m.error(line, vals["RPL"][1], f"RPL has no meaning in a {name} block")
        step = Affine(_diag(*(-1.0 if a in vals else 1.0 for a in AXES)), ZERO)
    new = ms.frame.then(step) if additive else step
    scales = [math.sqrt(sum(new.L[i][j] ** 2 for i in range(3))) for j in range(3)]
    if not all(SCALE_MIN <= f <= SCALE_MAX for f in scales):
        raise m.error(line, col, f"{name}: the frame would scale by {max(scales, key=lambda f: abs(math.log(f or 1e-300))):.6g}, "
                      f"beyond the permitted {SCALE_MIN:g} to {SCALE_MAX:g}")
    if not all(math.isfinite(v) and abs(v) <= FRAME_SHIFT_MAX for v in new.t):
        raise m.error(line, col, f"{name}: the frame's shift would leave the permitted range +-{FRAME_SHIFT_MAX:g} mm")
    ms.frame = new


def rotation(m, ms: Machine, vals: dict, name: str, line: int, col: int) -> Mat:
    """ROT RPL=a (in the active plane) or ROT X.. Y.. Z.. (about Z, then the new Y, then the new X)."""
    if "RPL" in vals:
        extra = [a for a in AXES if a in vals]
        if extra:
            raise m.error(line, vals[extra[0]][1], f"{name}: RPL= and an axis angle in one block")
        return _rot(PLANE_AXES[m.plane][2], vals["RPL"][0])
    r = IDENTITY
    for a in ("Z", "Y", "X"):
        if a in vals:
            r = mat_mul(r, _rot(AXES.index(a), vals[a][0]))
    return r


def cycles_in_frame(m, ms: Machine, src, blk, cycles: set) -> None:
    """A cycle called while a frame, an offset or inch units are active runs in the WCS and its moves
    are mapped into the machine afterwards (the cycles compute in the program's coordinates)."""
    line = src.line
    if any(getattr(st, "name", None) == "MCALL" for st in blk.calls):
        return  # MCALL CYCLE8x(..) only names the modal cycle: it runs after the moves (in_wcs)
    keep = []
    for stmt in blk.calls:
        name, args = getattr(stmt, "name", None), getattr(stmt, "args", None)
        if args is None or name not in cycles:
            keep.append(stmt)
            continue
        if any(a in blk.words for a in AXES) or m.comp_buf is not None:
            raise m.error(line, stmt.col, f"{name} under a frame: call the cycle in a block of its own, without "
                          "radius compensation")
        vals = [(None if x.value is None else m.ev(x.value, line, x.col), x.col) for x in args]
        # run from the move hook: after the block's spindle, tool and feed, as the interpreter's calls run
        ms.deferred.append((name, vals, src, stmt.col))
    blk.calls[:] = keep


def in_wcs(m, fn, name: str, line: int, col: int) -> None:
    """Run ``fn`` -- a cycle that moves the interpreter through m.rapid/m.linear/m.arc in program
    coordinates (mm) -- in the WCS of the active frames, its moves mapped into the machine. Without
    a frame it just runs. For every caller of a cycle (a modal MCALL cycle too). Inch units and
    SCALE are errors at ``line``:``col`` (the cycles compute with the tool radius in mm)."""
    ms = m.machine
    if ms.identity() or ms.sandbox:
        fn()
        return
    if ms.inch:
        raise m.error(line, col, f"{name} under G70/G700 (inch) is not modelled: the cycles work in mm")
    a = ms.frame.L if not ms.suppress else IDENTITY
    g = mat_mul(tuple(zip(*a)), a)  # type: ignore  # A^T A: I for a rotation or a mirror
    if any(abs(g[i][j] - (1.0 if i == j else 0.0)) > 1e-9 for i in range(3) for j in range(3)):
        raise m.error(line, col, f"{name} under SCALE is not modelled: the tool would have to scale too")
    run_mapped(m, ms, fn)


def run_mapped(m, ms: Machine, fn) -> None:
    """Run ``fn`` (which moves the interpreter in program coordinates) in the WCS: the position is
    taken back into the WCS, the records ``fn`` emits are mapped into the machine."""
    recs: list = []
    m.corner_flush()  # a move held for its corner goes out first, unmapped
    saved_records, saved_pos = m.program.records, list(m.pos)
    m.pos = list(ms.to_wcs(saved_pos))
    m.program.records = recs
    ms.sandbox = True
    try:
        fn()
        lathe.finish(m)  # a thread chain the cycle ends with gets its DITE run-out before the mapping
    finally:
        ms.sandbox = False
        m.program.records = saved_records
    m.pos = list(ms.to_machine(m.pos))
    for r in recs:
        m.program.records.append(map_record(m, ms, r))


def map_record(m, ms: Machine, r):
    if not isinstance(r, canon.MOTIONS):
        return r
    start, end = ms.to_machine(r.start), ms.to_machine(r.end)
    for p in (end, ms.to_machine(r.center) if isinstance(r, canon.Arc) else end):
        i = max(range(3), key=lambda k: abs(p[k]))
        if abs(p[i]) > COORD_LIMIT:
            raise CutsimError(r.src.program, r.src.line, r.src.col,
                              range_message(f"the point {AXES[i]} in the machine", p[i], -COORD_LIMIT, COORD_LIMIT, "mm"))
    if isinstance(r, canon.Arc):
        n = PLANE_AXES[r.plane][2]
        flip = plane_image(m, ms, r.plane, r.src.line, r.src.col)
        return replace(r, start=start, end=end, center=ms.to_machine(r.center), clockwise=r.clockwise != flip)
    if isinstance(r, canon.SyncedFeed):  # a cycle's thread: its lead axis must stay a turning axis
        i = AXES.index(r.lead_axis)
        lin = ms.linear_part()
        if any(abs(lin[i][k]) + abs(lin[k][i]) > 1e-12 for k in range(3) if k != i):
            raise m.error(r.src.line, r.src.col, "a thread under a rotated frame (ROT/AROT) is not modelled: the lead "
                          "axis would leave the turning axes")
        return replace(r, start=start, end=end, lead=r.lead * abs(lin[i][i]),
                       lead_change=r.lead_change * abs(lin[i][i]))
    return replace(r, start=start, end=end)


def plane_image(m, ms: Machine, plane: str, line: int, col: int) -> bool:
    """Check that the linear part maps the circle's plane onto itself as a similarity (a circle stays a
    circle in the same plane); True when it turns the plane over (the arc runs the other way)."""
    a, b, n = PLANE_AXES[plane]
    lin = ms.linear_part()
    ea, eb, en = (tuple(r[k] for r in lin) for k in (a, b, n))
    la, lb = math.sqrt(sum(x * x for x in ea)), math.sqrt(sum(x * x for x in eb))
    tilted = abs(ea[n]) > 1e-9 * la or abs(eb[n]) > 1e-9 * lb or abs(en[a]) > 1e-9 or abs(en[b]) > 1e-9
    if tilted:
        raise m.error(line, col, "a circle in a frame rotated about an axis of its plane (ROT/AROT X or Y in G17) "
                      "is not modelled in a 3-axis simulation: the circle would leave the plane")
    if abs(la - lb) > 1e-9 * max(la, lb) or abs(sum(x * y for x, y in zip(ea, eb))) > 1e-9 * la * lb:
        raise m.error(line, col, "a circle under SCALE with different factors for the axes of its plane would be an "
                      "ellipse: not modelled")
    return cofactor(lin)[n][n] < 0


# -- hook: move (the programmed point into the machine) ------------------------------------------------
def move(m, src, words: dict, run_cycle) -> None:
    """Turn the block's X/Y/Z, I/J/K and CR into machine values (absolute, mm) and track the extra
    axes; sets ``arc_flip`` for the interpreter's G2/G3. The cycles ``cycles_in_frame`` deferred run
    first, through ``run_cycle`` (milling.run_cycle, handed in by the interpreter)."""
    ms = m.machine
    ms.arc_flip = False
    line = src.line
    while ms.deferred:
        name, vals, csrc, col = ms.deferred.pop(0)
        in_wcs(m, lambda: run_cycle(m, name, vals, csrc, col), name, line, col)
    if m.cfg.axes:  # only axes the setup declares are taken from the words
        extra_axes(m, ms, src, words)
    arc = m.motion in (2, 3)
    if m.cfg.machine_kind == "lathe":
        lathe.x_words(m, ms, words, arc)  # DIAMON / DIAM90: X (and I=AC) diameters -> radii
    if ms.identity() or ms.sandbox:
        return
    if m.drill.mcall is not None and any(a in words for a in AXES) and not MODAL_CYCLES_IN_WCS:
        raise m.error(line, min(words[a].col for a in AXES if a in words),
                      f"a modal cycle (MCALL {m.drill.mcall[0]}) under a frame, an offset or inch units is not modelled yet")
    u = ms.unit()
    cur = ms.to_wcs(m.pos)
    given = [a for a in AXES if a in words]
    if given:
        target = list(cur)
        for i, a in enumerate(AXES):
            if a in words:
                w = words[a]
                ab = m.absolute if w.mode is None else w.mode == "AC"
                target[i] = w.value * u if ab else cur[i] + w.value * u
        mach = ms.to_machine(target)
        col = words[given[0]].col
        for i, a in enumerate(AXES):
            w = words[a] if a in words else Word(0.0, None, col)
            words[a] = replace(w, value=mach[i], mode="AC")
    if not arc:
        return
    pa, pb, _ = PLANE_AXES[m.plane]
    letters = (CENTRE_WORDS[pa], CENTRE_WORDS[pb])
    if "CR" in words or any(k in words for k in letters):
        col = min(words[k].col for k in ("CR", *letters) if k in words)
        ms.arc_flip = plane_image(m, ms, m.plane, line, col)
    if any(k in words for k in letters):
        centre = list(cur)
        for i, k in zip((pa, pb), letters):
            if k in words:
                w = words[k]
                centre[i] = w.value * u if w.mode == "AC" else cur[i] + w.value * u
        mc = ms.to_machine(centre)
        first = next(words[k] for k in letters if k in words)
        for i, k in zip((pa, pb), letters):
            words[k] = replace(words.get(k, first), value=mc[i], mode="AC")
    if "CR" in words:
        lin = ms.linear_part()
        scale = math.sqrt(sum(r[pa] ** 2 for r in lin))
        words["CR"] = replace(words["CR"], value=words["CR"].value * scale)


def extra_axes(m, ms: Machine, src, words: dict) -> None:
    line = src.line
    for name in [k for k in words if k in m.cfg.axes]:
        w = words.pop(name)
        rotary = m.cfg.axes[name] == "rotary"
        old = ms.axis_pos.get(name, 0.0)
        v = w.value if rotary else w.value * ms.unit()
        ab = m.absolute if w.mode is None else w.mode != "IC"  # AC, DC, ACP, ACN: absolute
        new = v if ab else old + v
        if abs(new - old) > EPS:
            if rotary and ms.traori:
                raise m.error(line, w.col, f"rotary axis {name} moves under TRAORI: a tilted tool is not modelled in "
                              "a 3-axis simulation")
            what = (f"rotary axis {name} moves; the simulation does not turn the workpiece" if rotary else
                    f"axis {name} moves; the simulation does not move it (only X, Y and Z carry the tool)")
            ms.warn_once(m, src, f"axis {name}", what)
        ms.axis_pos[name] = new


# -- hook: change_tool (M6) ----------------------------------------------------------------------------
def change_tool(m, src) -> bool:
    """T0 M6 empties the spindle (there is no tool 0): a tool change to no tool, after which the
    moves carry none and remove nothing; True when handled here."""
    if m.tool_pre != 0:
        return False
    if 0 in m.cfg.tool_radii:
        raise m.error(src.line, 1, "T0 M6 empties the spindle on a Sinumerik (there is no tool 0): the setup's "
                      "[[tool]] number = 0 cannot be selected; give it a number from 1")
    m.tool_no = None
    m.tool(src, None, None)
    return True


__all__ = ["Machine", "word", "g_codes", "settings", "move", "change_tool", "axis_message"]
