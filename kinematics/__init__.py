"""Kinematics: canonical records -> tool paths in the workpiece frame (lathe and mill models)."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from cutsim.base.specs import MachineSpec, ToolSpec
from cutsim.interp import canon
from cutsim.interp.errors import CutsimError

from .paths import ArcGeom, GaugePath, PlanarPath, RampGeom, ScrewPath, SpatialPath, arc_geom, arc_points
from .spindle import css_minutes, inverse_speed, revolutions, varying_spans

__all__ = ["ArcGeom", "GaugePath", "Plan", "plan", "PlanarPath", "ScrewPath", "SpatialPath"]


@dataclass
class Plan:
    paths: list = field(default_factory=list)
    warnings: list = field(default_factory=list)  # (Src, message)
    cycle_time: float = 0.0  # seconds
    final_position: tuple[float, float, float] = (0.0, 0.0, 0.0)  # program values


def plan(program: canon.Program, machine: MachineSpec, tools: list[ToolSpec], tol: float) -> Plan:
    """Turn the program's records into tool paths. Errors (unknown tool, G33 that cannot move)
    carry the record's source line."""
    return _Planner(program, machine, tools, tol).run()


class _Planner:
    def __init__(self, program, machine: MachineSpec, tools, tol):
        self.program, self.m, self.tol = program, machine, tol
        self.tools = {t.number: t for t in tools}
        self.tool = tools[0]
        self.out = Plan()
        self.spindle_dir = 0
        self.speed = 0.0
        self.css, self.limit = 0.0, 0.0  # constant cutting speed (m/min) and its limit (rpm): Sinumerik G96
        self.lathe = machine.kind == "lathe"
        self._warned_y = False

    def err(self, src, msg):
        return CutsimError(src.program, src.line, src.col, msg)

    def warn(self, src, msg):
        self.out.warnings.append((src, msg))

    def phys(self, p, diameter: bool) -> np.ndarray:
        """Program values -> physical coordinates (X radius on a diameter-programmed lathe)."""
        return np.array([p[0] / 2.0 if diameter else p[0], p[1], p[2]], dtype=float)

    def run(self) -> Plan:
        last_end = None
        for rec in self.program.records:
            if isinstance(rec, canon.Spindle):
                self.spindle_dir, self.speed = rec.direction, rec.speed
                self.css, self.limit = rec.css, rec.limit
            elif isinstance(rec, canon.ToolChange):
                if rec.tool is None:  # the spindle is emptied: the moves carry no tool (GaugePath)
                    self.tool = None
                elif rec.tool not in self.tools:
                    known = ", ".join(f"T{n}" for n in sorted(self.tools))
                    hint = ("; T0 empties the spindle only on a Sinumerik (T0 M6), elsewhere it selects the [[tool]] "
                            "with number = 0" if rec.tool == 0 else "")
                    raise self.err(rec.src, f"tool T{rec.tool} is not in the setup (tools: {known}){hint}")
                else:
                    self.tool = self.tools[rec.tool]
            elif isinstance(rec, canon.MOTIONS):
                self.motion(rec)
                last_end = rec
        if last_end is not None:
            self.out.final_position = tuple(float(v) for v in last_end.end)
        if self.program.final_position is not None:
            self.out.final_position = tuple(float(v) for v in self.program.final_position)
        return self.out

    # -- time ------------------------------------------------------------------------------------
    def feed_rate(self, rec) -> float:
        f = rec.feed
        if f <= 0:
            return self.m.feed
        if rec.per_rev:
            return f * self.speed if self.speed > 0 else self.m.feed
        return f

    # -- motions ---------------------------------------------------------------------------------
    def motion(self, rec) -> None:
        t = type(rec)
        if self.tool is None:
            self.gauge(rec)
            return
        if (t is canon.Rapid or t is canon.Feed) and not self.lathe:  # most moves: no numpy until the path
            s, e = rec.start, rec.end
            if rec.diameter:
                s, e = (s[0] / 2.0, s[1], s[2]), (e[0] / 2.0, e[1], e[2])
            dx, dy, dz = e[0] - s[0], e[1] - s[1], e[2] - s[2]
            length = math.sqrt(dx * dx + dy * dy + dz * dz)  # the squares summed in order, as np.linalg.norm
            rapid = t is canon.Rapid
            self.out.cycle_time += 60.0 * length / (self.m.rapid if rapid else self.feed_rate(rec))
            self.out.paths.append(SpatialPath(rec.src, self.tool, np.array((s, e), dtype=float), rapid))
            return
        p0 = self.phys(rec.start, rec.diameter)
        p1 = self.phys(rec.end, rec.diameter)
        if self.lathe and not self._warned_y and (abs(p0[1]) > 1e-9 or abs(p1[1]) > 1e-9):
            self.warn(rec.src, "a lathe has no Y axis: Y is ignored")
            self._warned_y = True
        if isinstance(rec, canon.SyncedFeed):
            self.synced(rec, p0, p1)
            return
        arc = None
        if isinstance(rec, canon.Arc):
            c = self.phys(rec.center, rec.diameter)
            pts = arc_points(p0, p1, c, rec.plane, rec.clockwise, rec.full_turn, self.tol)
            if not self.lathe:
                arc = arc_geom(p0, p1, c, rec.plane, rec.clockwise, rec.full_turn)
        else:
            pts = np.vstack([p0, p1])
        seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
        length = float(np.sum(seg))
        rapid = isinstance(rec, canon.Rapid)
        if not rapid and self.css > 0 and rec.per_rev and rec.feed > 0:  # G96: the speed follows the radius
            self.out.cycle_time += 60.0 * css_minutes(pts[:, 0], seg, rec.feed, self.css, self.limit)
        else:
            self.out.cycle_time += 60.0 * length / (self.m.rapid if rapid else self.feed_rate(rec))
        if self.lathe:
            if self.spindle_dir != 0:
                self.out.paths.append(PlanarPath(rec.src, self.tool, np.column_stack([pts[:, 0], pts[:, 2]]), rapid))
            else:
                self.out.paths.append(SpatialPath(rec.src, self.tool, pts * [1, 0, 1], rapid))
        else:
            self.out.paths.append(SpatialPath(rec.src, self.tool, pts, rapid, arc=arc))

    def gauge(self, rec) -> None:
        """A move with no tool in the spindle: the gauge point's path (an arc as its chords, a thread
        move along its ramps), timed as the move would be; it removes nothing."""
        p0, p1 = self.phys(rec.start, rec.diameter), self.phys(rec.end, rec.diameter)
        if isinstance(rec, canon.Arc):
            pts = arc_points(p0, p1, self.phys(rec.center, rec.diameter), rec.plane, rec.clockwise, rec.full_turn,
                             self.tol)
        elif isinstance(rec, canon.SyncedFeed):
            pts = np.vstack([p0, self.phys(rec.tool_end, rec.diameter)])
            travel = np.abs(pts[1] - pts[0])
            axis = "XYZ".index(rec.lead_axis) if rec.lead_axis else int(np.argmax(travel))
            if self.speed > 0 and (rec.lead > 0 or rec.lead_change > 0):
                self.out.cycle_time += 60.0 * revolutions(rec.lead, rec.lead_change, float(travel[axis])) / self.speed
        else:
            pts = np.vstack([p0, p1])
        rapid = isinstance(rec, canon.Rapid)
        if not isinstance(rec, canon.SyncedFeed):
            length = float(np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=1)))
            self.out.cycle_time += 60.0 * length / (self.m.rapid if rapid else self.feed_rate(rec))
        if self.lathe:
            pts = pts * [1, 0, 1]
        self.out.paths.append(GaugePath(rec.src, pts, rapid))

    def synced(self, rec: canon.SyncedFeed, p0, p1) -> None:
        if not self.lathe:
            raise self.err(rec.src, "G33 thread cutting needs a lathe (machine.kind = \"lathe\")")
        d = {"X": abs(p1[0] - p0[0]), "Z": abs(p1[2] - p0[2])}
        if rec.lead_axis is None:
            axis = "X" if d["X"] > d["Z"] else "Z"
        elif rec.lead_axis == "Y":
            raise self.err(rec.src, "a lathe has no Y axis to measure the lead along")
        else:
            axis = rec.lead_axis
        travel = d[axis]
        if travel <= 1e-9:
            raise self.err(rec.src, f"G33 does not move along {axis}, the axis its lead is measured on")
        revs = revolutions(rec.lead, rec.lead_change, travel)
        ramps = []
        for ramp, at_start in ((rec.leadin, True), (rec.runout, False)):
            if ramp is None:
                continue
            if ramp.axis == "Y":
                raise self.err(rec.src, "a lathe has no Y axis for the runout")
            if ramp.axis == axis:
                raise self.err(rec.src, f"the runout axis {ramp.axis} is the thread's own lead axis")
            start = 0.0 if at_start else travel - ramp.length
            ramps.append(RampGeom(start, ramp.length, ramp.displacement, "r" if ramp.axis == "X" else "z"))
        if self.css > 0:  # G96: the controller holds the speed it has at the thread's start
            self.out.cycle_time += 60.0 * revs * inverse_speed(p0[0], self.css, self.limit)
        elif self.speed > 0:
            self.out.cycle_time += 60.0 * revs / self.speed
        if self.spindle_dir == 0:
            self.warn(rec.src, "G33 with the spindle stopped: the controller would wait for the zero pulse forever; "
                               "the tool's own swept volume is removed")
            path = ScrewPath(rec.src, self.tool, p0[0], p0[2], p1[0], p1[2], travel, 0.0, 0.0, 1, tuple(ramps))
            s = np.array(path.breakpoints())
            r, z, _ = path.pose(s)
            self.out.paths.append(SpatialPath(rec.src, self.tool, np.column_stack([r, np.zeros_like(r), z]), False))
            return
        # M03 turns the spindle the positive way about +Z (machine.m03 may flip that); the cut
        # starts at spindle angle `start_angle` past the zero pulse in the direction of rotation,
        # and the tool meets the workpiece at minus the spindle angle.
        rot = self.spindle_dir * (1 if self.m.m03 == "positive" else -1)
        phi0 = -rot * rec.start_angle
        if rec.lead_change:
            self.varying(rec, p0, p1, travel, phi0, -rot)
            return
        self.out.paths.append(ScrewPath(rec.src, self.tool, p0[0], p0[2], p1[0], p1[2], travel, revs,
                                        phi0, -rot, tuple(ramps)))

    def varying(self, rec: canon.SyncedFeed, p0, p1, travel: float, phi0: float, sense: int) -> None:
        """G34/G35: chained constant-lead screws, each within the tolerance (kinematics/spindle.py)."""
        if rec.leadin is not None or rec.runout is not None:
            raise self.err(rec.src, "a thread with a varying lead and a lead-in or runout ramp is not modelled")
        try:
            spans = varying_spans(rec.lead, rec.lead_change, travel, self.tol)
        except ValueError as e:
            raise self.err(rec.src, str(e)) from None
        phi = phi0
        for t0, t1, revs in spans:
            a, b = p0 + (p1 - p0) * (t0 / travel), p0 + (p1 - p0) * (t1 / travel)
            self.out.paths.append(ScrewPath(rec.src, self.tool, a[0], a[2], b[0], b[2], t1 - t0, revs, phi, sense))
            phi += sense * 360.0 * revs
