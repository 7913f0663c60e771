"""LinuxCNC's standalone interpreter ``rs274`` as an oracle for the rs274ngc dialect.

``compare(program)`` runs cutsim's interpreter and ``rs274 -g`` on the same file and compares
their moves one by one; bench/vs_rs274.py and tests/interp/rs274ngc/test_rs274ngc_oracle.py both use it.

rs274's canonical calls are normalised to cutsim's records (machine frame, mm, tool tip):
- its coordinates are program coordinates: the G5x, G92 and tool length offsets it printed before
  (SET_G5X_OFFSET, SET_G92_OFFSET, USE_TOOL_LENGTH_OFFSET) are added, the loaded tool's length
  (CHANGE_TOOL, from the tool table) subtracted;
- it prints lengths in the units in effect (USE_LENGTH_UNITS): inches are multiplied by 25.4;
- this build's machine units are inches: the tool table and parameter file handed to it are the
  setup's (mm) divided by 25.4;
- in G7 its X is already a radius (cutsim's records are radii too);
- a synchronised move's lead is along its path in rs274 (START_SPEED_FEED_SYNC), along its lead axis in
  cutsim: cutsim's is scaled by the path length over the axis travel;
- an ARC_FEED of n turns is n arcs (whole turns first, the axis normal to the plane moving in
  proportion to the angle), as cutsim records it; RIGID_TAP is the synchronised move in and out;
- straight and synchronised moves shorter than 0.003 mm (rs274 prints 4 decimals of an inch; cutsim
  records no G33 to where the tool is) are left out on both sides,
  and one shorter than the tolerance is skipped where it does not match; feeds are compared where rs274 has one
  (an inverse-time F is its rate: cutsim's feed is that times the move's length).
rs274 prints 4 decimals in the units in effect: positions agree within 0.0006 units. Each run has
its own HOME: rs274 2.9 shares its tool table between runs through $HOME/.tool.mmap.
"""
from __future__ import annotations

import math
import os
import re
import shutil
import subprocess
import tempfile
from dataclasses import dataclass

from cutsim.interp import interpret
from cutsim.interp.canon import Arc, Feed, Rapid, SyncedFeed, describe
from cutsim.interp.errors import CutsimError
from cutsim.interp.core.modal import InterpConfig
from cutsim.interp.rs274ngc import files

INCH = 25.4
CALL = re.compile(r"^\s*(\d+) N\S*\s+([A-Z0-9_.]+)\((.*)\)\s*$")
PLANES = {"CANON_PLANE_XY": ("XY", 0, 1, 2), "CANON_PLANE_XZ": ("ZX", 2, 0, 1), "CANON_PLANE_YZ": ("YZ", 1, 2, 0)}
# the shared arc check's refusal of an arc whose end is off its circle by more than max(0.005 mm, 0.01 %),
# which LinuxCNC cuts as a spiral up to 0.028 mm (0.072 mm in G20) or 0.1 %: a documented limit
SPIRAL = "arc end point is not on the circle"
# the shared range of positions (core.lexer.COORD_LIMIT), which LinuxCNC does not have: a documented limit
RANGE = "exceeds the permitted range"
PROBE_BACKOFF = 0.01 * INCH  # mm: where rs274 leaves the tool after a probe move without contact
ZERO_MOVE = 0.003  # mm: a straight move shorter than rs274's printing resolution (4 decimals of an inch) is none
LENGTH_PARAMS = {5161, 5162, 5163, 5181, 5182, 5183, 5211, 5212, 5213,
                 *(5221 + 20 * n + i for n in range(9) for i in range(3))}


@dataclass
class Move:
    """A move in cutsim's terms: kind RAPID/FEED/ARC/SYNC, end point (mm, machine frame, X a radius),
    the in-plane centre, direction and plane of an arc, the feed or the lead."""

    kind: str
    start: tuple
    end: tuple
    text: str
    centre: tuple | None = None
    clockwise: bool | None = None
    plane: str | None = None
    feed: float | None = None
    per_rev: bool = False
    lead: float | None = None

    @property
    def length(self) -> float:
        return math.dist(self.start, self.end)


@dataclass
class Outcome:
    moves: list
    error: str | None


NO_END = "rs274 did not finish"
# G70-G72 are where rs274 2.9 is known to loop without end (LinuxCNC issues #1146, #2844; pull requests
# #1869, #2907, #3790 fix some of the loops after 2.9.0): docs/dialects/rs274ngc.md, "Differences that
# are rs274's"
G7X = re.compile(r"(?<![\d.])G0*7[012](?![\d])", re.IGNORECASE)


def rs274_path() -> str | None:
    return shutil.which("rs274")


def inch_files(tmp: str, tool_table: str | None, parameter_file: str | None) -> list[str]:
    """The options handing rs274 the setup's tool table and parameter file in its inches."""
    args = []
    if tool_table:
        path = os.path.join(tmp, "tools.tbl")
        with open(path, "w") as f:
            for t, e in sorted(files.tool_table(tool_table).items()):
                f.write(f"T{t} P{t} " + " ".join(f"{k}{v / INCH:.9f}" if k != "Q" else f"Q{v:g}"
                                                 for k, v in e.items()) + "\n")
        args += ["-t", path]
    if parameter_file:
        path = os.path.join(tmp, "params.var")
        with open(path, "w") as f:
            for n, v in sorted(files.parameter_file(parameter_file).items()):
                f.write(f"{n}\t{v / INCH if n in LENGTH_PARAMS else v:.9f}\n")
        args += ["-v", path]
    return args


def run_rs274(program: str, tool_table: str | None = None, parameter_file: str | None = None,
              timeout: float = 20.0) -> Outcome:
    """rs274's moves for ``program`` (normalised, see the module docstring), and its error if any."""
    with tempfile.TemporaryDirectory() as tmp:
        # subroutine files beside the program, where cutsim looks for them (rs274 only on SUBROUTINE_PATH)
        ini = os.path.join(tmp, "rs274.ini")
        with open(ini, "w") as f:
            f.write(f"[RS274NGC]\nSUBROUTINE_PATH = {os.path.dirname(os.path.abspath(program))}\n")
        args = [rs274_path() or "rs274", "-g", "-i", ini, *inch_files(tmp, tool_table, parameter_file),
                os.path.abspath(program)]
        try:
            # rs274 keeps its tool table in $HOME/.tool.mmap: two runs sharing a HOME read each other's
            # tables (a tool "not found", output lost, a bus error), so each run gets its own HOME
            proc = subprocess.run(args, cwd=tmp, stdin=subprocess.DEVNULL, capture_output=True, text=True,
                                  timeout=timeout, env=dict(os.environ, HOME=tmp))
        except subprocess.TimeoutExpired as stopped:
            # what it printed before it was stopped, up to its last whole line (a partial line dropped)
            out = stopped.stdout or b""
            out = out.decode("utf-8", "replace") if isinstance(out, bytes) else out
            tools = files.tool_table(tool_table) if tool_table else {}
            printed = parse(out[:out.rfind("\n") + 1], tools, 0).moves
            return Outcome(printed, f"{NO_END} within {timeout:g} s (a program that does not end)")
    tools = files.tool_table(tool_table) if tool_table else {}
    return parse(proc.stdout + "\n" + proc.stderr, tools, proc.returncode)


def parse(text: str, tools: dict, returncode: int = 0) -> Outcome:
    st = _State(tools)
    errors = []
    # rs274 writes "executing" into its output without a line break; a MESSAGE may hold the word too
    for raw in re.sub(r'(?<![ "\w])executing', "\n", text).splitlines():
        m = CALL.match(raw)
        if m is None:
            if raw.strip():
                errors.append(raw.strip())
            continue
        st.call(m.group(2), [a.strip() for a in m.group(3).split(",")] if m.group(3) else [], raw.strip())
    error = " / ".join(errors) if (errors or returncode) else None
    return Outcome(st.moves, error)


class _State:
    def __init__(self, tools: dict):
        self.tools = dict(tools)
        self.s = 1.0
        self.g5x = [0.0] * 3
        self.g92 = [0.0] * 3
        self.tlo = [0.0] * 3
        self.length = [0.0] * 3
        self.plane = PLANES["CANON_PLANE_XY"]
        self.pos = (0.0, 0.0, 0.0)
        self.canon = (0.0, 0.0, 0.0)  # where rs274's canonical layer put the tool last: printed + G5x + G92 (mm)
        self.feed, self.per_rev, self.lead = None, False, None
        self.moves: list[Move] = []

    def point(self, xyz) -> tuple:
        return tuple(float(xyz[i]) * self.s + self.g5x[i] + self.g92[i] + self.tlo[i] - self.length[i]
                     for i in range(3))

    def call(self, name: str, args: list[str], raw: str) -> None:
        if name == "USE_LENGTH_UNITS":
            self.s = INCH if "INCHES" in args[0] else 1.0
        elif name == "SET_G5X_OFFSET":
            self.g5x = [float(a) * self.s for a in args[1:4]]
        elif name == "SET_G92_OFFSET":
            self.g92 = [float(a) * self.s for a in args[0:3]]
        elif name == "USE_TOOL_LENGTH_OFFSET":
            vals = [float(v) for v in args[0].split()]
            self.tlo = [vals[0] * self.s, vals[1] * self.s, vals[2] * self.s]
        elif name == "CHANGE_TOOL":
            e = self.tools.get(int(args[0]), {})
            length = [e.get("X", 0.0), 0.0, e.get("Z", 0.0)]
            self.pos = tuple(self.pos[i] - length[i] + self.length[i] for i in range(3))  # the new tool's tip
            self.length = length
        elif name == "SET_TOOL_TABLE_ENTRY":  # G10 L1: offsets in its machine units (inch)
            vals = [float(v) * INCH for v in args[2].split()]
            self.tools[int(args[1])] = {"X": vals[0], "Z": vals[2]}
        elif name == "SELECT_PLANE":  # CANON_PLANE_UNKNOWN (G17.1-G19.1) has no arcs: the plane stays
            self.plane = PLANES.get(args[0], self.plane)
        elif name == "SET_FEED_RATE":
            self.feed = float(args[0]) * self.s
        elif name == "SET_FEED_MODE":
            self.per_rev = args[1] == "1"
        elif name == "START_SPEED_FEED_SYNC":
            self.lead = float(args[0]) * self.s
        elif name == "STOP_SPEED_FEED_SYNCH":
            self.lead = None
        elif name in ("STRAIGHT_TRAVERSE", "STRAIGHT_FEED", "STRAIGHT_PROBE"):
            end = self.point(args[0:3])
            if name == "STRAIGHT_PROBE":
                self.probe(args, end, raw)
            elif name == "STRAIGHT_TRAVERSE":
                self.add(Move("RAPID", self.pos, end, raw))
            elif self.lead is not None:
                self.add(Move("SYNC", self.pos, end, raw, lead=self.lead))
            else:
                self.add(Move("FEED", self.pos, end, raw, feed=self.feed, per_rev=self.per_rev))
        elif name == "RIGID_TAP":
            start = self.pos
            end = self.point(args[0:3])
            self.add(Move("SYNC", start, end, raw, lead=self.lead))
            self.add(Move("SYNC", end, start, raw, lead=self.lead))
        elif name == "ARC_FEED":
            self.arc(args, raw)

    def framed_of(self, point) -> tuple:
        """A point (machine frame) in rs274's canonical frame: without the tool length offset."""
        return tuple(point[i] - self.tlo[i] + self.length[i] for i in range(3))

    def probe(self, args: list[str], end: tuple, raw: str) -> None:
        """A feed to the probe point; then rs274 (no contact) leaves the tool 0.01 in back along the move
        as its canonical layer saw it (from where it last put the tool, tool length offsets not applied)."""
        start, stop = self.canon, self.framed_of(end)
        self.add(Move("FEED", self.pos, end, raw, feed=self.feed, per_rev=self.per_rev))
        length = math.dist(start, stop)
        if length > 0.0:
            self.pos = tuple(end[i] - PROBE_BACKOFF * (stop[i] - start[i]) / length for i in range(3))
            self.canon = tuple(stop[i] - PROBE_BACKOFF * (stop[i] - start[i]) / length for i in range(3))

    def arc(self, args: list[str], raw: str) -> None:
        plane, a, b, n = self.plane
        prog = [0.0, 0.0, 0.0]
        prog[a], prog[b], prog[n] = float(args[0]), float(args[1]), float(args[5])
        end = self.point(prog)
        cprog = list(prog)
        cprog[a], cprog[b] = float(args[2]), float(args[3])
        centre = self.point(cprog)
        turns = int(args[4])
        cw, turns = turns < 0, abs(turns)
        start = self.pos
        a0 = math.atan2(start[b] - centre[b], start[a] - centre[a])
        a1 = math.atan2(end[b] - centre[b], end[a] - centre[a])
        sweep = ((a0 - a1) if cw else (a1 - a0)) % (2 * math.pi)
        if math.hypot(end[a] - start[a], end[b] - start[b]) < ZERO_MOVE:  # full turns, as printed (rounded)
            sweep = 2 * math.pi
        total = sweep + 2 * math.pi * (turns - 1)
        for k in range(turns - 1):
            mid = list(self.pos)
            mid[n] = start[n] + (end[n] - start[n]) * 2 * math.pi * (k + 1) / total
            self.add(Move("ARC", self.pos, tuple(mid), raw, (centre[a], centre[b]), cw, plane, self.feed, self.per_rev))
        self.add(Move("ARC", self.pos, end, raw, (centre[a], centre[b]), cw, plane, self.feed, self.per_rev))

    def add(self, move: Move) -> None:
        self.pos = move.end
        self.canon = self.framed_of(move.end)
        if move.kind in ("RAPID", "FEED", "SYNC") and move.length < ZERO_MOVE:
            return
        self.moves.append(move)


def cutsim_moves(program: str, tool_table: str | None = None, parameter_file: str | None = None,
                 kind: str = "mill") -> Outcome:
    with open(program, encoding="utf-8") as f:
        text = f.read()
    cfg = InterpConfig(dialect="rs274ngc", machine_kind=kind, tool_table=tool_table or "",
                       parameter_file=parameter_file or "")
    try:
        prog = interpret(program, text, cfg)
    except CutsimError as e:
        return Outcome([], str(e))
    moves = []
    for r in prog.records:
        if isinstance(r, (Rapid, Feed, SyncedFeed)) and math.dist(r.start, r.end) < ZERO_MOVE:
            continue
        text = describe(r)
        if isinstance(r, Rapid):
            moves.append(Move("RAPID", r.start, r.end, text))
        elif isinstance(r, Feed):
            moves.append(Move("FEED", r.start, r.end, text, feed=r.feed, per_rev=r.per_rev))
        elif isinstance(r, Arc):
            a, b, _ = {"XY": (0, 1, 2), "ZX": (2, 0, 1), "YZ": (1, 2, 0)}[r.plane]
            moves.append(Move("ARC", r.start, r.end, text, (r.center[a], r.center[b]), r.clockwise, r.plane,
                              r.feed, r.per_rev))
        elif isinstance(r, SyncedFeed):
            # rs274's lead is along the path (LinuxCNC syncs the path length), cutsim's along its axis
            travel = abs(r.tool_end["XYZ".index(r.lead_axis)] - r.start["XYZ".index(r.lead_axis)]) if r.lead_axis else 0.0
            lead = r.lead * math.dist(r.start, r.tool_end) / travel if travel > 0.0 else r.lead
            moves.append(Move("SYNC", r.start, r.tool_end, text, lead=lead))
    return Outcome(moves, None)


def close(p, q, tol: float) -> bool:
    return all(abs(a - b) <= tol for a, b in zip(p, q))


def differ(ours: Move, theirs: Move, tol: float) -> str | None:
    """What differs between two moves (None: the same)."""
    if ours.kind != theirs.kind:
        return "kind"
    if not close(ours.end, theirs.end, tol):
        return "end point"
    if ours.kind == "ARC":
        if ours.plane != theirs.plane or ours.clockwise != theirs.clockwise:
            return "arc plane or direction"
        if not close(ours.centre, theirs.centre, tol):
            return "arc centre"
    if ours.kind in ("FEED", "ARC") and theirs.feed is not None:
        if ours.per_rev != theirs.per_rev:
            return "feed mode"
        per_minute = abs(ours.feed - theirs.feed) <= 1e-3 * max(1.0, abs(theirs.feed))
        inverse_time = abs(ours.feed - theirs.feed * _path(theirs)) <= 1e-3 * max(1.0, abs(ours.feed))
        if not (per_minute or inverse_time):
            return "feed"
    if ours.kind == "SYNC" and abs((ours.lead or 0.0) - (theirs.lead or 0.0)) > tol:
        return "lead"
    return None


def _path(m: Move) -> float:
    if m.kind != "ARC":
        return m.length
    _, a, b, n = PLANES[{"XY": "CANON_PLANE_XY", "ZX": "CANON_PLANE_XZ", "YZ": "CANON_PLANE_YZ"}[m.plane]]
    r = math.hypot(m.start[a] - m.centre[0], m.start[b] - m.centre[1])
    a0 = math.atan2(m.start[b] - m.centre[1], m.start[a] - m.centre[0])
    a1 = math.atan2(m.end[b] - m.centre[1], m.end[a] - m.centre[0])
    sweep = ((a0 - a1) if m.clockwise else (a1 - a0)) % (2 * math.pi) or 2 * math.pi
    return math.hypot(r * sweep, m.end[n] - m.start[n])


def compare(program: str, tool_table: str | None = None, parameter_file: str | None = None,
            kind: str = "mill", tol: float = 0.0006 * INCH) -> str:
    """"same", "same (both refuse: ...)", "documented difference: ..." (a difference docs/dialects/rs274ngc.md
    lists) or the first divergence with both lines."""
    ours = cutsim_moves(program, tool_table, parameter_file, kind)
    theirs = run_rs274(program, tool_table, parameter_file)
    if ours.error and theirs.error:
        return f"same (both refuse)\n  cutsim: {ours.error}\n  rs274:  {theirs.error}"
    if ours.error and not theirs.error and SPIRAL in ours.error:
        return (f"documented difference: an arc LinuxCNC cuts as a spiral, cutsim refuses (docs/dialects/rs274ngc.md, "
                f"Limits)\n  cutsim: {ours.error}\n  rs274:  {len(theirs.moves)} moves")
    if ours.error and not theirs.error and RANGE in ours.error:
        return (f"documented difference: a position beyond cutsim's range, which rs274 reaches (docs/dialects/"
                f"rs274ngc.md, Limits)\n  cutsim: {ours.error}\n  rs274:  {len(theirs.moves)} moves")
    if not ours.error and theirs.error and theirs.error.startswith(NO_END):
        return _no_end(program, ours.moves, theirs, tol)
    if ours.error or theirs.error:
        return (f"divergence: only {'cutsim' if ours.error else 'rs274'} refuses the program\n"
                f"  cutsim: {ours.error or f'{len(ours.moves)} moves'}\n  rs274:  {theirs.error or f'{len(theirs.moves)} moves'}")
    a, b = ours.moves, theirs.moves
    i, j, first = _walk(a, b, tol)
    if first:
        return first
    rest_a = [m for m in a[i:] if not _invisible(m, tol)]
    rest_b = [m for m in b[j:] if not _invisible(m, tol)]
    if rest_a or rest_b:
        who = "cutsim" if rest_a else "rs274"
        return f"divergence: {who} has {len(rest_a or rest_b)} more moves, the first: {(rest_a or rest_b)[0].text}"
    return "same"


def _walk(a: list, b: list, tol: float) -> tuple[int, int, str | None]:
    """Both move lists side by side while both last: where each stopped, and the first divergence."""
    i = j = 0
    while i < len(a) and j < len(b):
        why = differ(a[i], b[j], tol)
        if why is None:
            i, j = i + 1, j + 1
        elif _invisible(a[i], tol):
            i += 1
        elif _invisible(b[j], tol):
            j += 1
        else:
            return i, j, f"divergence at move {i + 1} ({why})\n  cutsim: {a[i].text}\n  rs274:  {b[j].text}"
    return i, j, None


def _no_end(program: str, ours: list, theirs: Outcome, tol: float) -> str:
    """rs274 stopped by the timeout, cutsim ran the program: rs274's known G7x loop (a documented
    difference) when the program has a G70-G72 and every move rs274 printed before it is cutsim's too
    (rs274 may stop printing mid-way: its last move is not compared), else a divergence."""
    with open(program, encoding="utf-8") as f:
        has_g7x = G7X.search(f.read()) is not None
    printed = theirs.moves[:-1]
    i, j, first = _walk(ours, printed, tol)
    if has_g7x and first is None and j == len(printed):
        return (f"documented difference: rs274 does not end on a G70-G72 cycle, its known loop (docs/dialects/"
                f"rs274ngc.md, Differences that are rs274's); its {len(printed)} moves before agree\n"
                f"  cutsim: {len(ours)} moves\n  rs274:  {theirs.error}")
    return (f"divergence: only rs274 refuses the program\n  cutsim: {len(ours)} moves\n"
            f"  rs274:  {theirs.error}" + (f"\n  before it: {first}" if first else ""))


def _invisible(m: Move, tol: float) -> bool:
    """A straight move shorter than the comparison's tolerance, which one side may drop and the other
    keep (a 0.003 mm move is 0.0030000001 on one side, 3.9107 - 3.9077 printed on the other): skipped
    where it does not match, since the next move's end is compared all the same."""
    return m.kind in ("RAPID", "FEED") and m.length < tol
