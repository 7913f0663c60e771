"""ISG variables and parameters: P parameters, V.P./V.S./V.L./V.E./V.G. variables with their
#VAR declarations, read and written by the expressions' closures (lang.py) and assignments."""
from __future__ import annotations

import math

from .lang import SCOPES
from .reader import IsgBlock, Section
from .tables import VALID_VAR, ZERO_VAR
from ..canon import Src
from ..core.modal import AXES

class Variables:
    """The variable store of Isg (a part of it). State: ``params`` (P parameters), ``vars`` (V.P.,
    V.S. and written V.E./V.G.), ``declared`` (V.P./V.S. name -> dims); V.L. live in the level."""

    params: dict
    vars: dict
    declared: dict

    def __init__(self, name, cfg):
        super().__init__(name, cfg)
        self.params = {f"P{k}": float(v) for k, v in cfg.parameters.items()}
        self.vars = {}
        self.declared = {}

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
                store = self.level.vl
            else:
                store = self.vars
                self.declared[d.name] = d.dims
            store[d.name] = d.dims
            for k, key in enumerate(_element_keys(d.name, d.dims)):
                store[key] = values[k] if k < len(values) else (values[0] if len(values) == 1 and not d.dims else 0.0)

    def read_param(self, key: str, line: int, col: int):
        store = self.level.params if key.startswith("@") else self.params
        if key not in store:
            what = "call parameter" if key.startswith("@") else "parameter"
            raise self.error(line, col, f"{what} {key} is read before it is assigned a value")
        return store[key]

    def read_var(self, scope: str, key: str, line: int, col: int):
        if scope == "L":
            if key in self.level.vl:
                return self._element(self.level.vl, key, line, col)
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
            if not self.level.cycle:
                raise self.error(line, col, f"{key} is read outside a cycle (the controller's error 21544: it tells "
                                 "a cycle whether its call programmed @P" + m.group(1) + ")")
            return 1.0 if f"@P{int(m.group(1))}" in self.level.params else 0.0
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
            return key in self.level.vl
        return key in self.vars or (scope not in ("P", "S") and key in self.cfg.variables)

    def _element(self, store: dict, key: str, line: int, col: int):
        v = store[key]
        if isinstance(v, tuple):
            raise self.error(line, col, f"{key} is an array: give its index ({key}[0])")
        return v

    def write_var(self, scope: str, key: str, value, line: int, col: int) -> None:
        if scope == "L":
            store = self.level.vl
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
                self.warn_once(("vp", key), Src(self.name, line, col, "", self.level.calls),
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
                self.level.params[key] = value
            else:
                self.params[key] = value
        else:
            _, scope, keyf = target
            self.write_var(scope, keyf(self), value, line, col)


def _element_keys(name: str, dims: tuple) -> list[str]:
    if not dims:
        return [name]
    keys = [name]
    for d in dims:
        keys = [f"{k}[{i}]" for k in keys for i in range(d)]
    return keys
