"""The setup file (TOML): machine, parameters, stock, tools, simulation. See docs/setup.md.

Every problem is a CutsimError naming the setup file, the line of the offending key, the table and
the key.
"""
from __future__ import annotations

import bisect
import math
import os
import re
import stat
import tomllib
from dataclasses import dataclass, field

from cutsim.base.specs import MachineSpec, StockSpec, ToolSpec
from cutsim.interp import DIALECTS  # the registry: names and each dialect's setup defaults
from cutsim.interp.errors import CutsimError
from cutsim.interp.modal import MAX_BLOCKS
from cutsim.stock.build import DEFAULT_MAX_TRIANGLES

KINDS = ("lathe", "mill")
TOOL_KEYS = {
    "thread": {"angle", "tip_radius", "height", "thickness"},
    "turning": {"angle", "tip_radius", "height", "thickness"},
    "profile": {"points", "thickness"},
    "endmill": {"diameter", "length", "corner_radius", "center_cutting"},
    "ballmill": {"diameter", "length"},
    "drill": {"diameter", "length", "point_angle"},
}
TOOL_COMMON = {"number", "kind", "name"}  # keys of every [[tool]]
TOOL_NAME_MAX = 32  # characters (a Sinumerik tool name is a STRING[32])
DRILL_LENGTH_FACTOR = 10.0  # a drill's default length: 10 x its diameter (a jobber drill's flutes)

# [[check]] kinds and their keys besides kind and name (docs/checks.md)
CHECK_KEYS = {
    "diameter": {"z", "expected", "tolerance", "angles"},
    "thread": {"z", "lead", "starts", "hand", "root_diameter", "phase", "phase_z", "tolerance", "lead_tolerance",
               "phase_tolerance", "angles"},
    "ramp": {"z", "radius", "diameter", "tolerance", "step"},
    "slot": {"at", "direction", "width", "floor", "center", "z", "tolerance"},
    "pocket": {"at", "size", "floor", "center", "z", "tolerance"},
    "depth": {"at", "z", "tolerance"},
    "volume": {"removed", "tolerance"},
    "design": {"path", "max_gouge", "max_excess", "max_deviation"},
}
LATHE_CHECKS = ("diameter", "thread", "ramp")
MILL_CHECKS = ("slot", "pocket", "depth")


@dataclass
class Setup:
    path: str
    machine: MachineSpec
    stock: StockSpec
    tools: list[ToolSpec]
    parameters: dict[int, float] = field(default_factory=dict)
    constants: dict[int, float] = field(default_factory=dict)
    tolerance: float = 0.002
    fail_on_warning: bool = False
    checks: list[dict] = field(default_factory=list)
    max_blocks: int = MAX_BLOCKS
    max_triangles: int = DEFAULT_MAX_TRIANGLES
    stock_where: tuple[int, int] = (0, 0)  # line, column of the key that sizes the stock (errors of build_stock)
    # what only the setup can say about the machine (docs/setup.md; interp.InterpConfig's fields of these names)
    axes: dict[str, str] = field(default_factory=dict)  # [machine] axes: extra axis name -> "rotary" | "linear"
    m_functions: frozenset[int] = frozenset()  # [machine] m_functions
    h_functions: frozenset[int] = frozenset()  # [machine] h_functions
    transformations: frozenset[str] = frozenset()  # [machine] transformations: Cartesian ones ("TRAFO")
    subprogram_path: tuple[str, ...] = ()  # [machine] subprogram_path: absolute folders
    external_subprograms: frozenset[str] = frozenset()  # [machine] external_subprograms: upper case, no folder
    variables: dict[str, float | str] = field(default_factory=dict)  # [variables]: upper-case name -> value
    work_offsets: dict[str, tuple[float, float, float]] = field(default_factory=dict)  # [work_offsets]: "G54" -> xyz
    tool_names: dict[str, int] = field(default_factory=dict)  # [[tool]] name (as written) -> number


# Ranges of the setup's numbers (docs/setup.md). Coordinates and sizes in mm.
COORD_MAX = 100_000.0  # |coordinate| of the stock, the start position, profile points
MIN_SIZE = 0.001  # smallest stock size (diameter, extent along an axis)
RATE_MAX = 1_000_000.0  # mm/min: rapid and default feed
VALUE_MAX = 1e12  # |R parameter| and |machine constant|
# The finest chordal tolerance: 0.1 um. The written mesh is snapped to a grid of at least 2^-16 mm
# (1.5e-5 mm; docs/setup.md, reports/mesh.py), so a finer tolerance could not survive the export, and
# circles at 1e-5 mm have thousands of segments whose booleans run for minutes (fuzz).
MIN_TOLERANCE = 1e-4
MAX_BLOCKS_LIMIT = 10_000_000  # every executed move is held until the run ends (~0.65 KB each): 6.5 GB at the ceiling
MAX_TRIANGLES_RANGE = (1_000, 2_000_000_000)
MAX_SETUP_BYTES = 16 * 1024 * 1024
FUNCTION_MAX = 99_999  # [machine] m_functions / h_functions: numbers 0 to this
STRING_MAX = 200  # characters of a string value in [variables] (a Sinumerik STRING holds at most 200)
AXIS_KINDS = ("rotary", "linear")
EXTERNAL_NAME_MAX = 64  # characters of an [machine] external_subprograms name (its folder removed)
# a subprogram, cycle file or G code the machine has: letters, digits, _ . - (0_INICIO_PROG.NC, G803, L_VENDOR)
_EXTERNAL_NAME = re.compile(r"[A-Z0-9_][A-Z0-9_.\-]*")
TRANSFORMATIONS = ("TRAFO",)  # [machine] transformations the dialects know (ISG #TRAFO ON)
# extra axis names: A B C U V W, optionally with a number (A1, C2), or two or three letters with a
# number (SP1; Sinumerik channel axis names, written NAME=value in the program). X, Y, Z are the machine's own.
_AXIS_NAME = re.compile(r"[ABCUVW][0-9]{0,2}|[A-Z]{2,3}[0-9]{1,2}")
# [variables] names (upper case, spaces inside [] removed): Sinumerik system variables $NAME[i, j]...,
# ISG V.<scope>.NAME[i].FIELD..., and plain names (Sinumerik global user data, NAME[i]).
_IDENT = r"[A-Z_][A-Z0-9_]*"
_INDEX = r"\[[A-Z0-9_.+\-]+(?:,[A-Z0-9_.+\-]+)*\]"
_VAR_NAME = re.compile(rf"\${_IDENT}(?:{_INDEX})*|V\.[A-Z]+(?:\.{_IDENT}(?:{_INDEX})*)+|{_IDENT}(?:{_INDEX})*")


def _number(v) -> bool:
    """A TOML number that is a finite float: not a bool, not nan/inf, not an integer too big for a float."""
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        return False
    try:
        return math.isfinite(float(v))
    except OverflowError:  # a 400-digit integer
        return False


def _coord(v) -> bool:
    return _number(v) and abs(v) <= COORD_MAX


def _show(v) -> str:
    """A value for a message, cut short (a hostile setup can hold huge arrays)."""
    text = repr(v)
    return text if len(text) <= 60 else text[:57] + "..."


class _Reader:
    """Typed access to one TOML table that remembers which keys were read."""

    def __init__(self, loader: "_Loader", table: dict, where: str, index: int | None = None):
        self.loader, self.table, self.where, self.index = loader, table, where, index
        self.used: set[str] = set()

    def fail(self, key: str | None, message: str) -> CutsimError:
        line, col = self.loader.locate(self.where, key, self.index)
        head = f"[{self.where}]" if self.index is None else f"[[{self.where}]] #{self.index + 1}"
        return CutsimError(self.loader.path, line, col, f"{head} {key + ': ' if key else ''}{message}")

    def get(self, key: str, kind, default=..., check=None, why: str = ""):
        self.used.add(key)
        if key not in self.table:
            if default is ...:
                raise self.fail(key, "is required")
            return default
        v = self.table[key]
        if kind is float:
            ok = _number(v)
            v = float(v) if ok else v
        elif kind is int:
            ok = isinstance(v, int) and not isinstance(v, bool)
        else:
            ok = isinstance(v, kind)
        if not ok:
            tname = {float: "a number", int: "a whole number", bool: "true or false", str: "a string",
                     list: "a list", dict: "a table"}[kind]
            raise self.fail(key, f"must be {tname}, not {_show(v)}")
        if check is not None and not check(v):
            raise self.fail(key, f"{why} (got {_show(v)})")
        return v

    def pair(self, key: str, default=..., increasing: bool = True):
        v = self.get(key, list, default)
        if v is default:
            return v
        if len(v) != 2 or not all(_number(c) for c in v):
            raise self.fail(key, f"must be two finite numbers [low, high], not {_show(v)}")
        if not all(_coord(c) for c in v):
            raise self.fail(key, f"must lie within -{COORD_MAX:g} to {COORD_MAX:g} mm, not {_show(v)}")
        if increasing and not v[0] < v[1]:
            raise self.fail(key, f"must be [low, high] with low < high, not {_show(v)}")
        return (float(v[0]), float(v[1]))

    def points(self, key: str, minimum: int = 3, maximum: int = 100_000):
        v = self.get(key, list)
        if not minimum <= len(v) <= maximum or not all(isinstance(p, list) and len(p) == 2 and
                                                       all(_number(c) for c in p) for p in v):
            raise self.fail(key, f"must be a list of {minimum} to {maximum} [a, b] pairs of finite numbers")
        if not all(_coord(c) for p in v for c in p):
            raise self.fail(key, f"coordinates must lie within -{COORD_MAX:g} to {COORD_MAX:g} mm")
        return tuple((float(p[0]), float(p[1])) for p in v)

    def size(self, key: str, lo: float, hi: float) -> None:
        """A stock size from ``lo`` to ``hi`` must be at least MIN_SIZE."""
        if hi - lo < MIN_SIZE:
            raise self.fail(key, f"the stock must be at least {MIN_SIZE:g} mm thick (got {hi - lo:g})")

    def fail_at(self, key: str, sub: tuple, message: str) -> CutsimError:
        """An error about a part of ``key``'s value (``sub``: element indexes / inner keys), at that part."""
        path = tuple(self.where.split(".")) + ((self.index,) if self.index is not None else ()) + (key,) + sub
        return CutsimError(self.loader.path, *self.loader.at(path), f"[{self.where}] {key}: {message}")

    def done(self) -> None:
        for key in self.table:
            if key not in self.used:
                raise self.fail(key, "unknown key")


class _Loader:
    def __init__(self, path: str, text: str):
        self.path = path
        self.text = text
        self.lines = text.splitlines()

        self._positions: dict[tuple, tuple[int, int]] | None = None

    def at(self, path: tuple) -> tuple[int, int]:
        """Line and column of the key or array element at ``path`` (table names, keys and element
        indexes), else of the nearest enclosing one that is written; 1:1 when none is."""
        if self._positions is None:
            self.locate("", None, None)
        while path:
            if path in self._positions:
                return self._positions[path]
            path = path[:-1]
        return (1, 1)

    def locate(self, table: str, key: str | None, index: int | None) -> tuple[int, int]:
        """Line and column of ``key`` in ``[table]`` (or its ``index``-th ``[[table]]``), however
        it is written (a table header, dotted keys, an inline table, an array of inline tables);
        the table when the key is absent; 1:1 when the table is absent too."""
        if self._positions is None:
            try:
                self._positions = _key_positions(self.text)
            except Exception:  # noqa: BLE001 - a position is a courtesy; never fail the error report
                self._positions = {}
        path = tuple(table.split(".")) + ((index,) if index is not None else ())
        if key is not None and path + (key,) in self._positions:
            return self._positions[path + (key,)]
        while path:
            if path in self._positions:
                return self._positions[path]
            path = path[:-1]
        return (1, 1)

    def load(self, data: dict) -> Setup:
        for top in data:
            if top not in ("machine", "parameters", "stock", "tool", "simulation", "check", "variables",
                           "work_offsets"):
                line, col = self.locate(top, None, None)
                raise CutsimError(self.path, line, col, f"unknown table [{top}]")
        for top in ("machine", "parameters", "stock", "simulation", "variables", "work_offsets"):
            if top in data and not isinstance(data[top], dict):
                raise CutsimError(self.path, *self.locate(top, None, None),
                                  f"[{top}] must be a table, not {_show(data[top])}")
        for top in ("tool", "check"):
            if top in data and isinstance(data[top], list):
                for i, t in enumerate(data[top]):
                    if not isinstance(t, dict):
                        raise CutsimError(self.path, *self.locate(top, None, i),
                                          f"[[{top}]] #{i + 1} must be a table, not {_show(t)}")
        if "machine" not in data:
            raise CutsimError(self.path, 1, 1, "the setup needs a [machine] table")
        sim = self.simulation(data.get("simulation"))
        m = _Reader(self, data["machine"], "machine")
        kind = m.get("kind", str, check=lambda v: v in KINDS, why=f"must be one of {', '.join(KINDS)}")
        dialect = m.get("dialect", str, check=lambda v: v in DIALECTS, why=f"must be one of {', '.join(DIALECTS)}")
        # when the setup does not say: the registry's default on a lathe (interp.DIALECTS), radii on a mill
        diam = m.get("diameter_programming", bool, DIALECTS[dialect].diameter_programming if kind == "lathe" else False)
        m03 = m.get("m03", str, "positive", check=lambda v: v in ("positive", "negative"), why="must be positive or negative")
        start = m.get("start", list, None)
        if start is not None:
            if len(start) != 3 or not all(_number(c) for c in start):
                raise m.fail("start", f"must be three finite numbers [x, y, z], not {_show(start)}")
            if not all(_coord(c) for c in start):
                raise m.fail("start", f"must lie within -{COORD_MAX:g} to {COORD_MAX:g}, not {_show(start)}")
            start = tuple(float(c) for c in start)
        rate = dict(check=lambda v: 0 < v <= RATE_MAX, why=f"must be more than 0 and at most {RATE_MAX:g} mm/min")
        rapid = m.get("rapid", float, 10000.0, **rate)
        feed = m.get("feed", float, 100.0, **rate)
        constants = {}
        consts = m.get("constants", dict, {})
        for k, v in consts.items():
            if not re.fullmatch(r"\d{1,6}", k):
                raise _Reader(self, consts, "machine.constants").fail(k, "constant names are numbers (0 to 999999)")
            c = _Reader(self, consts, "machine.constants")
            constants[int(k)] = c.get(k, float, check=lambda v: abs(v) <= VALUE_MAX,
                                      why=f"must lie within -{VALUE_MAX:g} to {VALUE_MAX:g}")
        axes = self.axes(m)
        m_functions = self.functions(m, "m_functions", "M")
        h_functions = self.functions(m, "h_functions", "H")
        transformations = self.transformations(m)
        subprogram_path = self.subprogram_path(m)
        external_subprograms = self.external_subprograms(m)
        m.done()
        machine = MachineSpec(kind, dialect, diam, m03, start, rapid, feed)

        params = {}
        if "parameters" in data:
            p = _Reader(self, data["parameters"], "parameters")
            for k in data["parameters"]:
                if not re.fullmatch(r"R\d{1,3}", k):
                    raise p.fail(k, "parameter names are R followed by a number (R04)")
                params[int(k[1:])] = p.get(k, float, check=lambda v: abs(v) <= VALUE_MAX,
                                           why=f"must lie within -{VALUE_MAX:g} to {VALUE_MAX:g}")

        if "stock" not in data:
            raise CutsimError(self.path, 1, 1, "the setup needs a [stock] table")
        stock, stock_where = self.stock(_Reader(self, data["stock"], "stock"), sim)

        tools = []
        raw_tools = data.get("tool", [])
        if not isinstance(raw_tools, list):
            raise CutsimError(self.path, *self.locate("tool", None, None), "tools are written [[tool]] (an array of tables)")
        numbers = set()
        tool_names: dict[str, int] = {}
        folded: dict[str, str] = {}  # casefolded name -> the name as first written
        for i, t in enumerate(raw_tools):
            tool = self.tool(_Reader(self, t, "tool", i), i)
            if tool.number in numbers:
                raise _Reader(self, t, "tool", i).fail("number", f"tool {tool.number} is defined twice")
            numbers.add(tool.number)
            if tool.name:
                other = folded.get(tool.name.casefold())
                if other is not None:
                    same = "names" if other == tool.name else f"differs only in case from {other!r}, which names"
                    raise _Reader(self, t, "tool", i).fail(
                        "name", f"{tool.name!r} {same} tool {tool_names[other]} already")
                folded[tool.name.casefold()] = tool.name
                tool_names[tool.name] = tool.number
            tools.append(tool)
        if not tools:
            raise CutsimError(self.path, 1, 1, "the setup needs at least one [[tool]]")
        for t in tools:
            if kind == "lathe" and not t.is_lathe_tool or kind == "mill" and t.is_lathe_tool:
                i = tools.index(t)
                raise _Reader(self, raw_tools[i], "tool", i).fail("kind", f"a {t.kind} tool does not fit a {kind}")

        tol, fow, max_blocks, max_triangles = sim
        raw_checks = data.get("check", [])
        if not isinstance(raw_checks, list):
            raise CutsimError(self.path, *self.locate("check", None, None), "checks are written [[check]] (an array of tables)")
        checks = [self.check(_Reader(self, c, "check", i), i, kind) for i, c in enumerate(raw_checks)]
        names = [c["name"] for c in checks]
        for i, c in enumerate(checks):
            if names.index(c["name"]) != i:
                raise _Reader(self, raw_checks[i], "check", i).fail("name", f"{c['name']!r} names two checks")
        variables = self.variables(data.get("variables", {}))
        work_offsets = self.work_offsets(data.get("work_offsets", {}), dialect)
        return Setup(self.path, machine, stock, tools, params, constants, tol, fow, checks, max_blocks,
                     max_triangles, stock_where, axes=axes, m_functions=m_functions, h_functions=h_functions,
                     subprogram_path=subprogram_path, variables=variables, work_offsets=work_offsets,
                     tool_names=tool_names, transformations=transformations,
                     external_subprograms=external_subprograms)

    # -- what only the setup can say about the machine (docs/setup.md) -----------------------------
    def axes(self, m: _Reader) -> dict[str, str]:
        """[machine] axes = { A = "rotary", W = "linear" }: the machine's extra axes."""
        table = m.get("axes", dict, {})
        r = _Reader(self, table, "machine.axes")
        out: dict[str, str] = {}
        for k in table:
            name = k.strip().upper()
            if re.fullmatch(r"[XYZ][0-9]*", name):
                raise r.fail(k, f"{name} is one of the machine's own axes X, Y, Z; declare only the extra ones "
                                "(A, B, C, U, V, W, ...)")
            if not _AXIS_NAME.fullmatch(name):
                raise r.fail(k, "an axis name is A, B, C, U, V or W, optionally with a number (A1, C2), or two or "
                                "three letters with a number (SP1)")
            if name in out:
                raise r.fail(k, f"axis {name} is declared twice")
            out[name] = r.get(k, str, check=lambda v: v in AXIS_KINDS, why='must be "rotary" or "linear"')
        return dict(sorted(out.items()))

    def functions(self, m: _Reader, key: str, letter: str) -> frozenset[int]:
        """[machine] m_functions / h_functions = [20, 70]: machine functions that pass silently."""
        v = m.get(key, list, [])
        for k, c in enumerate(v):
            if isinstance(c, str) and re.fullmatch(rf"\s*{letter}\s*0*\d{{1,5}}\s*", c, re.I):
                raise m.fail_at(key, (k,), f"write {c.strip()!r} as the number {int(c.strip()[1:])}")
            if not isinstance(c, int) or isinstance(c, bool) or not 0 <= c <= FUNCTION_MAX:
                raise m.fail_at(key, (k,), f"an {letter} function is a whole number from 0 to {FUNCTION_MAX}, "
                                           f"not {_show(c)}")
        return frozenset(v)

    def transformations(self, m: _Reader) -> frozenset[str]:
        """[machine] transformations = ["TRAFO"]: kinematic transformations under which the program's
        coordinates are the workpiece's Cartesian coordinates (ISG #TRAFO ON on a gantry or robot)."""
        v = m.get("transformations", list, [])
        for k, c in enumerate(v):
            if not isinstance(c, str) or c.strip().upper() not in TRANSFORMATIONS:
                raise m.fail_at("transformations", (k,), f"a transformation is one of {', '.join(TRANSFORMATIONS)}, "
                                                          f"not {_show(c)}")
        return frozenset(c.strip().upper() for c in v)

    def subprogram_path(self, m: _Reader) -> tuple[str, ...]:
        """[machine] subprogram_path = ["subs", ...]: folders searched for subprograms after the
        program's own, relative to the setup file's folder; each must exist."""
        v = m.get("subprogram_path", list, [])
        base = os.path.dirname(os.path.abspath(self.path))
        out: list[str] = []
        for k, d in enumerate(v):
            if not isinstance(d, str) or not d.strip():
                raise m.fail_at("subprogram_path", (k,), f"a folder is a non-empty string, not {_show(d)}")
            path = os.path.normpath(os.path.join(base, d))
            if not os.path.isdir(path):
                raise m.fail_at("subprogram_path", (k,), f"no such folder: {path}")
            if path not in out:
                out.append(path)
        return tuple(out)

    def external_subprograms(self, m: _Reader) -> frozenset[str]:
        """[machine] external_subprograms = ["0_Inicio_Prog.nc", "G803", "L_VENDOR"]: subprograms,
        cycle files and implicit-call G codes the machine has but the simulator does not (vendor
        cycles whose source the user does not have). Each is kept as its file name (the part after
        the last / or \\), upper-cased; a name given twice (in any case or folder) is an error."""
        key = "external_subprograms"
        v = m.get(key, list, [])
        out: dict[str, int] = {}
        for k, c in enumerate(v):
            if not isinstance(c, str) or not c.strip():
                raise m.fail_at(key, (k,), f"a subprogram is a non-empty string (its name or file name), not {_show(c)}")
            name = re.split(r"[/\\]", c.strip())[-1].strip().upper()
            if not name:
                raise m.fail_at(key, (k,), f"{_show(c)} is a folder: name the subprogram's file")
            if len(name) > EXTERNAL_NAME_MAX:
                raise m.fail_at(key, (k,), f"a subprogram name has at most {EXTERNAL_NAME_MAX} characters "
                                           f"(got {len(name)})")
            if not _EXTERNAL_NAME.fullmatch(name):
                raise m.fail_at(key, (k,), f"{_show(c)}: a subprogram name is letters, digits, _ . and - "
                                           "(L_VENDOR, G803, 0_Inicio_Prog.nc), not starting with . or -")
            if name in out:
                raise m.fail_at(key, (k,), f"{name} is given twice (also element {out[name] + 1})")
            out[name] = k
        return frozenset(out)

    def variables(self, table: dict) -> dict[str, float | str]:
        """[variables]: values of system variables, PLC data, machine data and global user data the
        program reads. Names upper-cased, spaces inside [] removed; an unquoted dotted ISG name
        (V.G.X = 1, a nested table to TOML) is joined back with dots."""
        out: dict[str, float | str] = {}

        todo: list[tuple[tuple, object]] = [((k,), v) for k, v in reversed(table.items())]
        while todo:  # depth first, in the order written (no recursion: a dotted key may have any depth)
            here, v = todo.pop()
            if isinstance(v, dict):
                todo.extend((here + (k,), w) for k, w in reversed(v.items()))
                continue
            written = ".".join(here)
            at = self.at(("variables",) + here)
            head = f"[variables] {written if len(written) <= 60 else written[:57] + '...'}: "

            def fail(message):
                return CutsimError(self.path, *at, head + message)

            name = re.sub(r"\[[^\]]*\]", lambda mt: re.sub(r"\s+", "", mt.group()), written.strip().upper())
            if not _VAR_NAME.fullmatch(name):
                raise fail("a variable name is a system variable ($P_TOOLNO, $A_DBB[5], $MA_JOG_VELO[X1]), an "
                           "ISG V. variable (V.G.NAME, V.E.SPEED) or a global user data name (MYDATA[2]), "
                           "written without spaces")
            if re.fullmatch(r"R[0-9]+", name):
                raise fail(f"R parameters are set in [parameters] ({name} = ...)")
            if name in out:
                raise fail(f"{name} is given twice")
            if isinstance(v, bool):
                out[name] = 1.0 if v else 0.0
            elif isinstance(v, (int, float)):
                if not _number(v) or abs(v) > VALUE_MAX:
                    raise fail(f"must be a finite number within -{VALUE_MAX:g} to {VALUE_MAX:g}, not {_show(v)}")
                out[name] = float(v)
            elif isinstance(v, str):
                if len(v) > STRING_MAX:
                    raise fail(f"a string value has at most {STRING_MAX} characters (got {len(v)})")
                out[name] = v
            else:
                raise fail(f"must be a number, a string or true/false, not {_show(v)}")
        return dict(sorted(out.items()))

    def work_offsets(self, table: dict, dialect: str) -> dict[str, tuple[float, float, float]]:
        """[work_offsets] G54 = [x, y, z]: the settable work offsets (mm) the program selects."""
        r = _Reader(self, table, "work_offsets")
        if dialect == "sinumerik":
            names = [f"G{n}" for n in (*range(54, 58), *range(505, 600))]
            known = "G54 to G57 and G505 to G599"
        else:
            names = [f"G{n}" for n in range(54, 60)]
            known = "G54 to G59"
        out: dict[str, tuple[float, float, float]] = {}
        for k in table:
            name = k.strip().upper()
            if name in ("G500", "G53", "G153", "SUPA"):
                raise r.fail(k, f"{name} is no work offset (it switches the settable offsets off); "
                                f"the offsets are {known}")
            if dialect == "sinumerik" and name in ("G58", "G59"):
                raise r.fail(k, f"on Sinumerik {name} is a programmable axial offset written in the program; "
                                f"the settable offsets are {known}")
            if name == "G92":
                raise r.fail(k, "G92 is set by the program, not the setup")
            if name not in names:
                raise r.fail(k, f"the work offsets of {dialect} are {known}")
            if name in out:
                raise r.fail(k, f"{name} is given twice")
            v = r.get(k, list)
            if len(v) != 3 or not all(_number(c) for c in v):
                raise r.fail(k, f"must be three finite numbers [x, y, z], not {_show(v)}")
            if not all(_coord(c) for c in v):
                raise r.fail(k, f"must lie within -{COORD_MAX:g} to {COORD_MAX:g} mm, not {_show(v)}")
            out[name] = (float(v[0]), float(v[1]), float(v[2]))
        return dict(sorted(out.items(), key=lambda kv: int(kv[0][1:])))

    def simulation(self, table: dict | None) -> tuple[float, bool, int, int]:
        """[simulation]: tolerance, fail_on_warning, max_blocks, max_triangles (read first: the
        stock is checked against the tolerance and the triangle limit)."""
        if table is None:
            return 0.002, False, MAX_BLOCKS, DEFAULT_MAX_TRIANGLES
        s = _Reader(self, table, "simulation")
        tol = s.get("tolerance", float, 0.002, check=lambda v: MIN_TOLERANCE <= v <= 1.0, why="must be between 0.0001 and 1 mm")
        fow = s.get("fail_on_warning", bool, False)
        max_blocks = s.get("max_blocks", int, MAX_BLOCKS, check=lambda v: 1 <= v <= MAX_BLOCKS_LIMIT,
                           why=f"must be at least 1 and at most {MAX_BLOCKS_LIMIT:,}")
        lo, hi = MAX_TRIANGLES_RANGE
        max_tri = s.get("max_triangles", int, DEFAULT_MAX_TRIANGLES, check=lambda v: lo <= v <= hi,
                        why=f"must be a whole number from {lo:,} to {hi:,}")
        s.done()
        return tol, fow, max_blocks, max_tri

    def check(self, c: _Reader, i: int, machine_kind: str) -> dict:
        """One [[check]] table as a plain dict (see docs/checks.md); keys by kind in CHECK_KEYS."""
        kind = c.get("kind", str, check=lambda v: v in CHECK_KEYS, why=f"must be one of {', '.join(CHECK_KEYS)}")
        if kind in LATHE_CHECKS and machine_kind != "lathe" or kind in MILL_CHECKS and machine_kind != "mill":
            raise c.fail("kind", f"a {kind} check needs a {'lathe' if kind in LATHE_CHECKS else 'mill'}")
        allowed = CHECK_KEYS[kind] | {"kind", "name"}
        for k in c.table:
            if k not in allowed:
                raise c.fail(k, f"unknown key for a {kind} check (known: {', '.join(sorted(allowed - {'kind'}))})")
        line, _col = self.locate("check", None, i)
        spec: dict = {"kind": kind, "name": c.get("name", str, f"{kind} #{i + 1}", check=lambda v: v.strip() != "",
                                                  why="must not be empty"), "index": i, "line": line}
        pos = dict(check=lambda v: v > 0, why="must be positive")
        nonneg = dict(check=lambda v: v >= 0, why="must not be negative")

        def xy(key, default=...):
            v = c.get(key, list, default)
            if v is default:
                return v
            if len(v) != 2 or not all(_number(q) for q in v):
                raise c.fail(key, f"must be two numbers [x, y], not {_show(v)}")
            return (float(v[0]), float(v[1]))

        if kind == "diameter":
            spec["z"] = c.get("z", float)
            spec["expected"] = c.get("expected", float, **pos)
            spec["tolerance"] = c.get("tolerance", float, 0.02, **nonneg)
            spec["angles"] = c.get("angles", int, 72, check=lambda v: 4 <= v <= 3600, why="must be 4 to 3600")
        elif kind == "thread":
            spec["z"] = c.pair("z")
            spec["lead"] = c.get("lead", float, **pos)
            spec["starts"] = c.get("starts", int, 1, check=lambda v: 1 <= v <= 16, why="must be 1 to 16")
            spec["hand"] = c.get("hand", str, "right", check=lambda v: v in ("right", "left"), why="must be right or left")
            spec["root_diameter"] = c.get("root_diameter", float, None, **pos)
            spec["tolerance"] = c.get("tolerance", float, 0.02, **nonneg)
            spec["lead_tolerance"] = c.get("lead_tolerance", float, 0.005, **nonneg)
            spec["phase_tolerance"] = c.get("phase_tolerance", float, 2.0, **nonneg)
            spec["angles"] = c.get("angles", int, 36, check=lambda v: 8 <= v <= 720, why="must be 8 to 720")
            phase = c.get("phase", list, None)
            if phase is not None:
                if not all(_number(q) for q in phase):
                    raise c.fail("phase", f"must be a list of angles in degrees, not {_show(phase)}")
                if len(phase) != spec["starts"]:
                    raise c.fail("phase", f"needs one angle per start ({spec['starts']}), got {len(phase)}")
                spec["phase"] = [float(q) for q in phase]
                spec["phase_z"] = c.get("phase_z", float)
            else:
                spec["phase"] = None
                if "phase_z" in c.table:
                    raise c.fail("phase_z", "is only used with phase")
        elif kind == "ramp":
            spec["z"] = c.pair("z")
            has_r, has_d = "radius" in c.table, "diameter" in c.table
            if has_r == has_d:
                raise c.fail(None, "a ramp check needs exactly one of radius = [r1, r2] or diameter = [d1, d2]")
            if has_r:
                spec["radius"] = c.pair("radius", increasing=False)
            else:
                d = c.pair("diameter", increasing=False)
                spec["radius"] = (d[0] / 2, d[1] / 2)
            spec["tolerance"] = c.get("tolerance", float, 0.02, **nonneg)
            spec["step"] = c.get("step", float, 0.1, **pos)
        elif kind in ("slot", "pocket"):
            spec["at"] = xy("at")
            spec["floor"] = c.get("floor", float, None)
            spec["z"] = c.get("z", float, None)
            spec["tolerance"] = c.get("tolerance", float, 0.02, **nonneg)
            if kind == "slot":
                spec["direction"] = c.get("direction", str, check=lambda v: v in ("x", "y"), why="must be x or y")
                spec["width"] = c.get("width", float, None, **pos)
                spec["center"] = c.get("center", float, None)
                wanted = ("width", "floor", "center")
            else:
                spec["size"] = c.pair("size", None, increasing=False)
                if spec["size"] is not None and min(spec["size"]) <= 0:
                    raise c.fail("size", "widths must be positive")
                spec["center"] = xy("center", None)
                wanted = ("size", "floor", "center")
            if all(spec[k] is None for k in wanted):
                raise c.fail(None, f"a {kind} check needs at least one of {', '.join(wanted)}")
        elif kind == "depth":
            spec["at"] = xy("at")
            spec["expected"] = c.get("z", float)
            spec["tolerance"] = c.get("tolerance", float, 0.02, **nonneg)
        elif kind == "volume":
            spec["removed"] = c.get("removed", float, **nonneg)
            spec["tolerance"] = c.get("tolerance", float, None, **nonneg)
        elif kind == "design":
            rel = c.get("path", str)
            path = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(self.path)), rel))
            if not os.path.isfile(path):
                raise c.fail("path", f"no such file: {path}")
            spec["path"] = path
            spec["max_gouge"] = c.get("max_gouge", float, 0.01, **nonneg)
            spec["max_excess"] = c.get("max_excess", float, None, **nonneg)
            spec["max_deviation"] = c.get("max_deviation", float, None, **nonneg)
            spec["column"] = self.locate("check", "path", i)[1]
            spec["path_line"] = self.locate("check", "path", i)[0]
        c.done()
        return spec

    def stock(self, s: _Reader, sim: tuple) -> tuple[StockSpec, tuple[int, int]]:
        """The [stock] table and where its size is written (the line build_stock's errors name).
        Ranges: coordinates within COORD_MAX, sizes at least MIN_SIZE, and the solid at the
        setup's tolerance within [simulation] max_triangles."""
        from cutsim.kinematics.paths import circle_segments
        from cutsim.stock.build import load_mesh_stock

        tol, max_tri = sim[0], sim[3]
        shape = s.get("shape", str, check=lambda v: v in ("cylinder", "revolve", "box", "mesh"),
                      why="must be cylinder, revolve, box or mesh")
        key = {"cylinder": "diameter", "revolve": "profile", "box": "x", "mesh": "path"}[shape]
        if shape == "cylinder":
            d = s.get("diameter", float, check=lambda v: MIN_SIZE <= v <= 2 * COORD_MAX,
                      why=f"must be from {MIN_SIZE:g} to {2 * COORD_MAX:g} mm")
            z = s.pair("z")
            s.size("z", *z)
            spec = StockSpec(shape, diameter=d, z=z)
        elif shape == "revolve":
            prof = s.points("profile")
            if any(r < 0 for r, _ in prof):
                raise s.fail("profile", "radii must not be negative")
            if _area(prof) == 0:
                raise s.fail("profile", "the outline encloses no area")
            if max(r for r, _ in prof) < MIN_SIZE or max(z for _, z in prof) - min(z for _, z in prof) < MIN_SIZE:
                raise s.fail("profile", f"the stock must be at least {MIN_SIZE:g} mm in radius and in height")
            spec = StockSpec(shape, profile=prof)
        elif shape == "box":
            box = {a: s.pair(a) for a in ("x", "y", "z")}
            for a, (lo, hi) in box.items():
                s.size(a, lo, hi)
            spec = StockSpec(shape, **box)
        else:
            rel = s.get("path", str)
            path = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(self.path)), rel))
            if not os.path.isfile(path):
                raise s.fail("path", f"no such file: {path}")
            spec = StockSpec(shape, path=path)
        s.done()
        where = self.locate("stock", key, None)
        if shape == "mesh":  # read and checked now, so its errors name the path key's line (cached)
            load_mesh_stock(spec.path, self.path, where=where, max_triangles=max_tri, max_coord=COORD_MAX,
                            min_size=MIN_SIZE)
        elif shape in ("cylinder", "revolve"):
            outline = 4 if shape == "cylinder" else len(spec.profile)
            tris = 2 * outline * circle_segments(spec.bounds()[1][0], tol)
            if tris > max_tri:
                raise s.fail(key, f"at the tolerance {tol:g} mm the stock would have about {tris:,} triangles, "
                                  f"more than [simulation] max_triangles = {max_tri:,}")
        return spec, where

    def tool(self, t: _Reader, i: int) -> ToolSpec:
        number = t.get("number", int, i + 1, check=lambda v: v >= 0, why="must not be negative")
        kind = t.get("kind", str, check=lambda v: v in TOOL_KEYS, why=f"must be one of {', '.join(TOOL_KEYS)}")
        allowed = TOOL_KEYS[kind]
        for k in t.table:
            if k not in allowed | TOOL_COMMON:
                raise t.fail(k, f"unknown key for a {kind} tool (known: {', '.join(sorted(allowed | {'name'}))})")
        name = t.get("name", str, "", check=_tool_name_ok,
                     why=f"must be 1 to {TOOL_NAME_MAX} characters without quotes, control characters or "
                         "spaces at either end")
        # types here; ranges (docs/setup.md) in stock/tools.py, shared with tools built in Python
        from cutsim.stock.tools import SIZE_MAX, tool_problem

        kw: dict = {}
        if kind in ("thread", "turning"):
            kw["angle"] = t.get("angle", float, 60.0 if kind == "thread" else 55.0)
            kw["tip_radius"] = t.get("tip_radius", float, 0.0 if kind == "thread" else 0.4)
            kw["height"] = t.get("height", float, 10.0)
        if kind == "profile":
            kw["points"] = t.points("points")
        if kind in ("thread", "turning", "profile"):
            kw["thickness"] = t.get("thickness", float, 5.0)
        if kind in ("endmill", "ballmill"):
            kw["diameter"] = t.get("diameter", float)
            kw["length"] = t.get("length", float, min(4.0 * kw["diameter"], SIZE_MAX))
            if kind == "endmill":
                kw["corner_radius"] = t.get("corner_radius", float, 0.0)
                kw["center_cutting"] = t.get("center_cutting", bool, True)
            else:
                kw["corner_radius"] = kw["diameter"] / 2
        if kind == "drill":
            kw["diameter"] = t.get("diameter", float)
            kw["length"] = t.get("length", float, min(DRILL_LENGTH_FACTOR * kw["diameter"], SIZE_MAX))
            kw["point_angle"] = t.get("point_angle", float, 118.0)
        t.done()
        line, col = self.locate("tool", None, i)
        spec = ToolSpec(number, kind, **kw, name=name, source=self.path, line=line, col=col)
        bad = tool_problem(spec)
        if bad is not None:
            key, why = bad
            raise t.fail(key, why)  # at the key's line, or the table's when the key is a default
        return spec


def _tool_name_ok(v: str) -> bool:
    return (0 < len(v) <= TOOL_NAME_MAX and v == v.strip() and '"' not in v
            and all(c.isprintable() for c in v))


def _area(pts) -> float:
    return 0.5 * abs(sum(x0 * y1 - x1 * y0 for (x0, y0), (x1, y1) in zip(pts, pts[1:] + pts[:1])))


_BARE_KEY = re.compile(r"[A-Za-z0-9_\-]+")
_SCALAR = re.compile(r"[^,\]\}\r\n#]*")


def _key_positions(text: str) -> dict[tuple, tuple[int, int]]:
    """(line, column) of every key of a TOML text that tomllib accepted, by its full path: table
    names and keys as strings, the n-th ``[[table]]`` or array element as the integer n. Header
    tables map to their header line; dotted keys and inline tables to the key itself; array
    elements to the element's first character."""
    starts = [0] + [m.end() for m in re.finditer("\n", text)]
    n = len(text)
    pos: dict[tuple, tuple[int, int]] = {}

    def lc(i: int) -> tuple[int, int]:
        row = bisect.bisect_right(starts, i) - 1
        return row + 1, i - starts[row] + 1

    def ws(i: int, newlines: bool = False) -> int:
        while i < n:
            c = text[i]
            if c in " \t\r" or newlines and c == "\n":
                i += 1
            elif newlines and c == "#":
                while i < n and text[i] != "\n":
                    i += 1
            else:
                break
        return i

    def string_end(i: int) -> int:
        q = text[i]
        if text.startswith(q * 3, i):
            j = text.find(q * 3, i + 3)
            if j < 0:
                return n
            while j + 3 < n and text[j + 3] == q:  # up to two quotes just before the closing ones
                j += 1
            return j + 3
        j = i + 1
        while j < n and text[j] != q and text[j] != "\n":
            j += 2 if q == '"' and text[j] == "\\" else 1
        return j + 1

    def key(i: int):
        parts, at = [], []
        while i < n:
            i = ws(i)
            at.append(i)
            if i < n and text[i] in "\"'":
                j = string_end(i)
                parts.append(tomllib.loads("k = " + text[i:j])["k"])
                i = j
            else:
                m = _BARE_KEY.match(text, i)
                if not m:
                    break
                parts.append(m.group())
                i = m.end()
            i = ws(i)
            if i < n and text[i] == ".":
                i += 1
                continue
            break
        return parts, at, i

    def value(i: int, path: tuple) -> int:
        c = text[i] if i < n else ""
        if c in ("\"", "'"):
            return string_end(i)
        if c in ("[", "{"):
            close, k = ("]" if c == "[" else "}"), 0
            i += 1
            while True:
                i = ws(i, True)
                if i >= n or text[i] == close:
                    return i + 1
                if c == "[":
                    pos.setdefault(path + (k,), lc(i))
                    i = value(i, path + (k,))
                    k += 1
                else:
                    i = keyval(i, path)
                i = ws(i, True)
                if i < n and text[i] == ",":
                    i += 1
                elif i < n and text[i] != close:
                    return i  # not TOML after all: give up on this value
        return _SCALAR.match(text, i).end()

    def keyval(i: int, path: tuple) -> int:
        parts, at, i = key(i)
        if not parts:
            return i + 1
        for d in range(len(parts)):
            pos.setdefault(path + tuple(parts[:d + 1]), lc(at[d]))
        i = ws(i)
        if i < n and text[i] == "=":
            i = ws(i + 1)
        return value(i, path + tuple(parts))

    table: tuple = ()
    arrays: dict[tuple, int] = {}  # [[name]] -> index of its last element
    headers: set[tuple] = set()
    i = 0
    while True:
        i = ws(i, True)
        if i >= n:
            break
        start = i
        if text[i] == "[":
            double = text.startswith("[[", i)
            parts, _at, i = key(i + (2 if double else 1))
            full: tuple = ()
            for d, p in enumerate(parts):
                full += (p,)
                if d < len(parts) - 1 and full in arrays:
                    full += (arrays[full],)
            if double:
                arrays[full] = arrays.get(full, -1) + 1
                pos.setdefault(full, lc(start))
                full += (arrays[full],)
            if full not in headers:  # an explicit header names the table (not an earlier sub-table)
                headers.add(full)
                pos[full] = lc(start)
            for d in range(1, len(full)):
                pos.setdefault(full[:d], lc(start))
            table = full
            i = text.find("]", i)
            i = i + (2 if double else 1) if i >= 0 else n
        else:
            i = keyval(i, table)
        while i < n and text[i] != "\n":  # the rest of the line: spaces and a comment
            if text[i] == "#":
                i = text.find("\n", i)
                i = n if i < 0 else i
                break
            i += 1
    return pos


def load_setup(path: str) -> Setup:
    """Read and validate a setup file. Raises CutsimError (exit status 2 in the CLI)."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except (OSError, ValueError) as e:
        raise CutsimError(path, 0, 0, f"cannot read the setup: {getattr(e, 'strerror', None) or e}") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise CutsimError(path, 0, 0, "cannot read the setup: not a regular file")
        with os.fdopen(os.dup(fd), "rb") as f:
            raw = f.read(MAX_SETUP_BYTES + 1)
    except OSError as e:
        raise CutsimError(path, 0, 0, f"cannot read the setup: {e.strerror}") from None
    finally:
        os.close(fd)
    if len(raw) > MAX_SETUP_BYTES:
        raise CutsimError(path, 0, 0, f"the setup is larger than {MAX_SETUP_BYTES >> 20} MiB")
    try:
        text = raw.decode("utf-8-sig")  # a byte order mark is accepted
    except UnicodeDecodeError as e:
        bom = 3 if raw.startswith(b"\xef\xbb\xbf") else 0
        at = e.start + bom  # the decoder counts from after the byte order mark
        ls = raw.rfind(b"\n", 0, at) + 1
        head = raw[max(ls, bom):at].decode("utf-8")
        raise CutsimError(path, raw.count(b"\n", 0, at) + 1, len(head) + 1,
                          f"the setup is not UTF-8 text (byte 0x{raw[at]:02x} at offset {at})") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        line = getattr(e, "lineno", 0) or 0
        col = getattr(e, "colno", 0) or 0
        msg = getattr(e, "msg", str(e))
        where = re.search(r"\s*\(at line (\d+), column (\d+)\)$", msg)  # Python < 3.14: only in the text
        if where:
            line, col = line or int(where.group(1)), col or int(where.group(2))
            msg = msg[:where.start()]
        end = re.search(r"\s*\(at end of document\)$", msg)
        if end or not line:  # the error is where the text ends
            msg = msg[:end.start()] + " (at the end of the file)" if end else msg
            line, col = text.count("\n") + 1, len(text) - (text.rfind("\n") + 1) + 1
        raise CutsimError(path, line, col, f"not valid TOML: {msg}") from None
    except ValueError as e:  # tomllib's int() of a number with more digits than Python converts
        line, col = huge_number_at(text)
        reason = str(e).split(";")[0]  # without Python's advice (sys.set_int_max_str_digits)
        raise CutsimError(path, line, col, f"not valid TOML: a number with too many digits ({reason})") from None
    except RecursionError:  # tomllib reads nested arrays and inline tables recursively
        raise CutsimError(path, 1, 1, "arrays or inline tables are nested too deeply") from None
    return _Loader(path, text).load(data)


def huge_number_at(text: str) -> tuple[int, int]:
    """(line, column) of the first run of more than 4300 digits (Python's limit for int of a string,
    which tomllib raises as a plain ValueError), or the start of the text."""
    m = re.search(r"[0-9_]{4300,}", text)
    if not m:
        return 1, 1
    return text.count("\n", 0, m.start()) + 1, m.start() - (text.rfind("\n", 0, m.start()) + 1) + 1
