"""Cutter radius compensation one block behind, as LinuxCNC 2.9 does it (interp/core/compensation.py
offsets a whole contour between selection and deselection; this follows the program move by move).

Each move is offset when the next one is known: the first move in the plane after the selection goes
from where the tool stands to the offset of its programmed end (perpendicular to the move there; an
arc re-centred to fit), and at each corner the turn between the programmed directions decides - a
concave corner trims the move waiting in the queue back to where the two offset paths meet (a line
that would then run backwards, an arc that would grow, is a gouge), a convex one gets an arc about
the programmed corner (a rapid goes straight), a turn under ``SMALL_TURN`` gets neither. The angles
and the choice between two crossing points are LinuxCNC's (rs274 measured move by move:
tests/interp/rs274ngc/test_rs274ngc_oracle.py), so the paths agree to its printed digits.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .compensation import _dot, _norm, _p2, _p3, _sub, _add
from .modal import PLANE_AXES

SMALL_TURN = 0.05  # rad: a corner turning less than this gets no arc and no trim (rs274 2.9, measured)


def find_turn(p, c, turn: int, q) -> float:
    """The signed angle (radians, + counter-clockwise) an arc of ``turn`` turns (LinuxCNC's count:
    +n counter-clockwise, -n clockwise) sweeps about ``c`` from ``p`` to ``q``; start = end is a whole turn."""
    if turn == 0:
        return 0.0
    a0 = math.atan2(p[1] - c[1], p[0] - c[0])
    a1 = math.atan2(q[1] - c[1], q[0] - c[0])
    if turn > 0:
        if a1 <= a0:
            a1 += 2 * math.pi
        return a1 - a0 + (turn - 1) * 2 * math.pi
    if a0 <= a1:
        a0 += 2 * math.pi
    return a1 - a0 + (turn + 1) * 2 * math.pi


def _polar(p, r: float, ang: float):
    return (p[0] + r * math.cos(ang), p[1] + r * math.sin(ang))


def _angle(p, q) -> float:
    """Direction from ``p`` to ``q``."""
    return math.atan2(q[1] - p[1], q[0] - p[0])


@dataclass
class Cut:
    """A move waiting for the next one to decide its end: ``kind`` "L" (feed), "R" (rapid) or "A" (arc),
    or "-" (a record that is no move, kept in order). ``way``: a line's programmed direction, which its
    compensated run may not reverse; ``sweep``: an arc's programmed angle (0: a corner arc)."""
    kind: str
    rec: object
    end: tuple = (0.0, 0.0)
    axis: float = 0.0  # the coordinate along the plane's normal at the end
    way: tuple = (0.0, 0.0)
    centre: tuple = (0.0, 0.0)
    turn: int = 0
    sweep: float = 0.0


class QueuedComp:
    """One selection of cutter radius compensation (module docstring). Moves along the plane's normal
    only are done where the tool stands. Work is in the plane's (a, b) coordinates of the nose centre,
    starting where the control point stands (as rs274 does); ``shift`` moves every output point from
    the nose centre to the control point (a lathe tool's orientation).

    ``side`` +1 left (G41), -1 right (G42); ``start`` the tool's position (3D) at selection; ``memory``
    LinuxCNC's start of the queue, kept by the caller from one selection to the next (rs274 does);
    ``out(cut, start, end, centre)`` takes each finished move (3D points of the control point; ``None``
    for a record that is no move); errors come from ``error(message)`` of the block being
    converted."""

    def __init__(self, side: int, radius: float, plane: str, start, shift, memory: dict, out):
        self.side, self.r, self.plane = side, radius, plane
        self.shift = shift
        self.a, self.b, self.n = PLANE_AXES[plane]
        self.prog = self.cur = (start[self.a], start[self.b])  # rs274: the control point counts as the centre
        self.axis = start[self.n]
        self.first = True
        self.queue: list[Cut] = []
        self.memory = memory  # {"endpoint": (a, b), "valid": bool}
        self.out = out
        self.pos = start  # the end of the last move handed out (3D, control point)

    # -- the queue ---------------------------------------------------------------------------------
    def keep(self, rec) -> None:
        """A record that is no move, kept in its place among the moves."""
        self.queue.append(Cut("-", rec))

    def _set_start(self, p) -> None:
        self.memory["endpoint"], self.memory["valid"] = p, True

    def _dequeue(self) -> None:
        for cut in self.queue:
            if cut.kind == "-":
                self.out(cut, None, None, None)
                continue
            end = _p3(_add(cut.end, self.shift), cut.axis, self.plane)
            centre = _p3(_add(cut.centre, self.shift), self.pos[self.n], self.plane) if cut.kind == "A" else None
            self.out(cut, self.pos, end, centre)
            self.pos = end
        self.queue = []

    def _move_end(self, p, mm: bool, error) -> None:
        """Every queued move ends at ``p`` now; a line turned back or an arc grown is a gouge."""
        if not self.queue:
            return
        start, valid = self.memory.get("endpoint", (0.0, 0.0)), self.memory.get("valid", False)
        for cut in self.queue:
            if cut.kind == "A":
                r1, r2 = _norm(_sub(cut.end, cut.centre)), _norm(_sub(p, cut.centre))
                if abs(r1 - r2) > 0.01 * (1.0 if mm else 25.4):
                    raise error("cutter compensation made an arc whose radii do not match")
                grown = abs(find_turn(start, cut.centre, cut.turn, p)) > abs(cut.sweep) + (0.0254 if mm else 0.001)
                if cut.sweep and valid and grown:
                    raise error("Arc move in concave corner cannot be reached by the tool without gouging")
            elif cut.kind in "LR" and valid and _dot(cut.way, _sub(p, start)) < 0:
                what = "feed" if cut.kind == "L" else "traverse"
                raise error(f"Straight {what} in concave corner cannot be reached by the tool without gouging")
            if cut.kind != "-":
                cut.end = p
        self._dequeue()
        self._set_start(p)

    def jump(self, p3) -> None:
        """The nose's position becomes the programmed point ``p3`` (no move): rs274 2.9 after a G70
        under compensation has read its profile (which ended at ``p3``)."""
        self.cur = _p2(p3, self.plane)

    def finish(self, mm: bool, error) -> None:
        """Deselection or the program's end: the last move ends where it is."""
        self._move_end(self.cur, mm, error)

    def _inside(self, turn: int) -> bool:
        """The tool runs on the centre's side of an arc of ``turn`` (G41 counter-clockwise, G42 clockwise)."""
        return (self.side > 0 and turn > 0) or (self.side < 0 and turn < 0)

    def _front_arc(self):
        """The move waiting at the queue's front when it is an arc (LinuxCNC joins from it), else None."""
        return self.queue[0] if self.queue and self.queue[0].kind == "A" else None

    # -- straight moves ----------------------------------------------------------------------------
    def line(self, rec, rapid: bool, mm: bool, error) -> None:
        """A G0/G1 move to ``rec.end`` (programmed)."""
        p, axis = _p2(rec.end, self.plane), rec.end[self.n]
        kind = "R" if rapid else "L"
        if self.first:
            if _norm(_sub(p, self.cur)) <= self.r:
                raise error("Length of cutter compensation entry move is not greater than the tool radius")
            ang = _angle(self.cur, p) + self.side * math.pi / 2
            end = _polar(p, self.r, ang)
            self._set_start(self.cur)
            self.queue.append(Cut(kind, rec, end, axis, (math.cos(ang), math.sin(ang))))
            self.first = False
        elif p == self.prog:  # along the normal only: where the tool stands
            end = self.cur
            self.queue.append(Cut(kind, rec, end, axis))
        else:
            end = self._line_corner(p, rapid, rec, mm, error)
            self.queue.append(Cut(kind, rec, end, axis, _sub(p, self.prog)))
        self.prog, self.cur, self.axis = p, end, axis

    def _line_corner(self, p, rapid: bool, rec, mm: bool, error):
        """Join the queued move to a line to ``p``; returns the line's offset end."""
        o, c, left = self.prog, self.cur, self.side > 0
        theta, alpha = _angle(o, c), _angle(o, p)
        if left:
            if theta < alpha:
                theta += 2 * math.pi
            beta, gamma = theta - alpha - math.pi / 2, math.pi / 2
        else:
            if alpha < theta:
                alpha += 2 * math.pi
            beta, gamma = alpha - theta - math.pi / 2, -math.pi / 2
        end = _polar(p, self.r, alpha + gamma)
        mid = _polar(o, self.r, alpha + gamma)
        prev = self._front_arc()
        concave = beta < -SMALL_TURN or beta > math.pi + SMALL_TURN or (
            beta > math.pi - SMALL_TURN and prev is not None and not self._inside(prev.turn))
        if concave and prev is None:  # line -> line: back along the previous move to the meeting point
            half = (beta + math.pi) / 2
            if half == 0.0:
                raise error("Zero degree inside corner is invalid for cutter compensation")
            self._move_end(_polar(c, self.r / math.tan(half), theta + gamma), mm, error)
        elif concave:
            self._move_end(self._arc_line_meet(prev, p, error), mm, error)
        elif beta > SMALL_TURN:  # convex: round the programmed corner (a rapid goes straight)
            self._move_end(c, mm, error)
            if rapid:
                self.queue.append(Cut("R", rec, mid, self.axis))
            else:
                self.queue.append(Cut("A", rec, mid, self.axis, centre=o, turn=-1 if left else 1))
            self._dequeue()
            self._set_start(mid)
        else:
            self._dequeue()
            self._set_start(c)
        return end

    def _arc_line_meet(self, prev: Cut, p, error):
        """Where the offset of the line ``prog`` -> ``p`` meets the queued (offset) arc ``prev``."""
        o = self.prog
        oldrad = _norm(_sub(prev.end, prev.centre))
        base = _angle(o, p)
        theta = base + math.pi / 2 if prev.turn > 0 else base - math.pi / 2
        phi = _angle(o, prev.centre)
        inside = self._inside(prev.turn)
        d = (oldrad + self.r if inside else oldrad - self.r) * math.cos(theta - phi)
        ratio = (d - self.r if inside else d + self.r) / oldrad
        if ratio > 1.0 or ratio < -1.0:
            raise error("Arc to straight motion makes a corner the compensated tool can't fit in without gouging")
        sign = -1.0 if (inside == (prev.turn > 0)) else 1.0
        return _polar(prev.centre, oldrad, sign * math.acos(ratio) + theta + math.pi)

    # -- arcs ----------------------------------------------------------------------------------------
    def arc(self, rec, centre3, turn: int, mm: bool, error) -> None:
        """A G2/G3 move to ``rec.end`` about ``centre3`` (programmed) of ``turn`` turns (+ counter-clockwise)."""
        p, axis, centre = _p2(rec.end, self.plane), rec.end[self.n], _p2(centre3, self.plane)
        radius = _norm(_sub(centre, p))
        inside = self._inside(turn)
        if inside and radius <= self.r:
            raise error("Tool radius not less than arc radius with comp")
        out = _angle(p, centre) if inside else _angle(centre, p)
        end = _polar(p, self.r, out)
        if self.first:
            self._entry_arc(rec, p, end, centre, turn, axis, error)
        else:
            self._arc_corner(rec, p, end, centre, turn, radius, mm, error)
            self.queue.append(Cut("A", rec, end, axis, centre=centre, turn=turn,
                                  sweep=find_turn(self.prog, centre, turn, p)))
        self.prog, self.cur, self.axis = p, end, axis

    def _entry_arc(self, rec, p, end, centre, turn: int, axis: float, error) -> None:
        """The first move is an arc: one from the tool to the offset end, its centre on the line from
        that end through the programmed centre (so it meets the programmed arc's offset there)."""
        c = self.cur
        if _norm(_sub(p, c)) <= self.r:
            raise error("Radius of cutter compensation entry arc is not greater than the tool radius")
        half = _norm(_sub(c, end)) / 2.0
        towards = _angle(end, centre)
        corner = _angle(end, c) - towards
        if abs(math.cos(corner)) < 0.0001:
            raise error("Tool radius not less than arc radius with comp")
        new_centre = _polar(end, half / math.cos(corner), towards)
        if self.shift != (0.0, 0.0):  # rs274 moves the tool to the nose centre's start first
            self.queue.append(Cut("L", rec, c, self.axis))
            self._set_start(c)
        self.queue.append(Cut("A", rec, end, axis, centre=new_centre, turn=turn,
                              sweep=find_turn(c, new_centre, turn, end)))
        self.first = False

    def _arc_corner(self, rec, p, end, centre, turn: int, radius: float, mm: bool, error) -> None:
        """Join the queued move to an arc starting at the programmed point ``prog``."""
        o, c, left = self.prog, self.cur, self.side > 0
        theta = _angle(o, c) + (-math.pi / 2 if left else math.pi / 2)
        delta = _angle(o, centre)
        alpha = delta - math.pi / 2 if turn > 0 else delta + math.pi / 2
        beta = theta - alpha if left else alpha - theta
        beta = beta - 2 * math.pi if beta > 1.5 * math.pi else beta + 2 * math.pi if beta < -math.pi / 2 else beta
        inside = self._inside(turn)
        if not inside:
            delta += math.pi
        if beta < -SMALL_TURN or beta > math.pi + SMALL_TURN or (abs(beta - math.pi) < SMALL_TURN and not inside):
            prev = self._front_arc()
            if prev is None:  # line -> arc
                dist = radius - self.r if inside else radius + self.r
                toward = radius * math.sin(beta - math.pi / 2) + (self.r if inside else -self.r)
                ratio = toward / dist
                if ratio > 1.0 or ratio < -1.0:
                    raise error("Arc move in concave corner cannot be reached by the tool without gouging")
                swing = math.asin(ratio) if turn > 0 else -math.asin(ratio)
                ang = theta + swing if inside else theta + math.pi - swing
                meet = _polar(centre, dist, ang)
            else:  # arc -> arc: where the two offset circles cross
                oldrad = _norm(_sub(prev.centre, prev.end))
                newrad = radius - self.r if inside else radius + self.r
                cc = _norm(_sub(prev.centre, centre))
                if oldrad == 0 or cc == 0:
                    raise error("Arc to arc motion is invalid because the arcs have the same center")
                cosine = (oldrad * oldrad + cc * cc - newrad * newrad) / (2 * oldrad * cc)
                if cosine > 1.0 or cosine < -1.0:
                    raise error("Arc to arc motion makes a corner the compensated tool can't fit in without gouging")
                pull = math.acos(cosine) if (self._inside(prev.turn) == (turn > 0)) else -math.acos(cosine)
                meet = _polar(prev.centre, oldrad, _angle(prev.centre, centre) + pull)
            self._move_end(meet, mm, error)
        elif beta > SMALL_TURN:  # convex: round the programmed corner
            mid = _polar(o, self.r, delta)
            self._dequeue()
            self.queue.append(Cut("A", rec, mid, self.axis, centre=o, turn=-1 if left else 1))
            self._dequeue()
            self._set_start(mid)
        else:
            self._dequeue()
            self._set_start(c)
