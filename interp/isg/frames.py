"""ISG coordinate frames: zero offsets (G53..G59, V.G.NP), G92, #CS, #MCS, the contour rotation
(#ROTATION, G68) and mirroring (G20..G23, G351), composed as one core.frames.Affine."""
from __future__ import annotations

from ..core import Step
from ..core.frames import Affine, IDENTITY, turn
from ..core.lexer import Word
from ..core.modal import AXES, PLANE_AXES

class Frames:
    """The program frame of Isg (a part of it). State: ``zero`` (the G54..G59 offset), ``npv``
    (zero offsets the program wrote: i -> [x, y, z]), ``g92``, ``cs`` (active #CS: a stack of
    (x, y, z, degrees about Z)), ``cs_defs`` / ``cs_last`` (#CS DEF), ``mcs`` (#MCS ON),
    ``rotation`` ((angle, plane, centre 1, centre 2)), ``mirror`` (per axis), ``turned`` (a rotation
    or mirroring is active: targets go through program_frame) and ``turned_linear`` (its linear part)."""

    def __init__(self, name, cfg):
        super().__init__(name, cfg)
        self.zero = (0.0, 0.0, 0.0)
        self.npv: dict[int, list] = {}
        self.g92 = [0.0, 0.0, 0.0]
        self.cs: list[tuple] = []
        self.cs_defs: dict[int, tuple] = {}
        self.cs_last: int | None = None
        self.mcs = False
        self.rotation: tuple | None = None
        self.mirror = [False, False, False]
        self.turned = False
        self.turned_linear = IDENTITY

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
