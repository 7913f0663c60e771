"""ISG tool radius compensation G40/G41/G42 (G25/G26 transitions, G138/G139 selection): the records
between selection and deselection are buffered and offset by core.compensation. On a lathe it is
the tool nose radius compensation of the turning functions: the offset is the nose radius and the
path is moved from the nose's centre to the tool's theoretical tip by its cutting edge position
(TwinCAT CNC tool data, "cutter position" 1-9)."""
from __future__ import annotations

import dataclasses

from .tables import TRC_METHODS
from .. import canon
from ..canon import Src
from ..core import Group, Step
from ..errors import CutsimError
from ..core.compensation import compensate_records, nose_shift
from ..core.lexer import Word
from ..core.modal import PLANE_AXES

def x_scaled(rec, k: float):
    """A record with its X values (and an arc's centre X) multiplied by ``k`` when it is in diameter
    mode: 0.5 turns diameters into the radii the offset geometry needs, 2.0 turns them back."""
    if not isinstance(rec, canon.MOTIONS) or not rec.diameter:
        return rec

    def sx(p):
        return (p[0] * k, p[1], p[2])
    kw = {"start": sx(rec.start), "end": sx(rec.end)}
    if isinstance(rec, canon.Arc):
        kw["center"] = sx(rec.center)
    return dataclasses.replace(rec, **kw)


class Compensation:
    """Tool radius compensation of Isg (a part of it). State: ``tool_no`` / ``d_zero`` (the active
    tool, D0), ``comp`` (40/41/42), ``comp_buf`` (records buffered while it is on), ``comp_radius``,
    ``comp_plane``, ``comp_off`` (G40 programmed: the next motion in the plane departs),
    ``trc_linear`` (G25/G26), ``trc_method`` ((code, word) of the selection method), ``comp_flip``
    (-1: a mirrored plane at selection swaps the side)."""

    def __init__(self, name, cfg):
        super().__init__(name, cfg)
        self.tool_no: int | None = next(iter(cfg.tool_radii), None)
        self.d_zero = False
        self.comp = 40
        self.comp_buf: list | None = None
        self.comp_radius = 0.0
        self.comp_plane = ""
        self.comp_off = False
        self.trc_linear = True
        self.trc_method: tuple = (139, None)
        self.comp_flip = 1.0

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
            self.warn_once(("WZ_AKT.R", self.tool_no, self.d_zero), Src(self.name, line, col, "", self.level.calls),
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
        if self.cfg.machine_kind == "lathe":
            return float(self.cfg.tool_noses.get(self.tool_no, (0.0, 9))[0])
        return float(self.cfg.tool_radii.get(self.tool_no, 0.0))

    def nose_edge(self) -> int:
        """The active lathe tool's cutting edge position (1-9; 9 when unknown: the centre)."""
        return self.cfg.tool_noses.get(self.tool_no, (0.0, 9))[1] if self.tool_no is not None else 9

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
        lathe = self.cfg.machine_kind == "lathe"
        if lathe and self.plane != "ZX":
            raise self.error(line, g.col, f"G{code} on a lathe in the plane {self.plane}: tool nose radius compensation "
                             "works in the turning plane (G18, ZX)")
        self.check_trc_method(st, g, "select it")
        r = self.trc_radius()
        if r == 0:
            what = "nose radius" if lathe else "tool radius"
            self.warn(st.src, f"G{code} with {what} 0 (the setup gives none for the active tool, or D0): "
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
        lathe = self.cfg.machine_kind == "lathe"
        shift = nose_shift(self.nose_edge(), self.comp_radius, self.comp_plane) if lathe else (0.0, 0.0)
        if lathe:
            buf = [x_scaled(r, 0.5) for r in buf]
        recs = compensate_records(buf, side * self.comp_radius, self.comp_plane, departure,
                                  self.trc_method[0] == 138, self.trc_linear, err, shift=shift)
        if lathe:
            recs = [x_scaled(r, 2.0) for r in recs]
        self.program.records.extend(recs)
        for rec in reversed(recs):
            if isinstance(rec, canon.MOTIONS):
                self.moved(rec.end)
                break
