"""The [machine] table and what else only the setup can say about the machine the program runs on:
[parameters], [variables] and [work_offsets] (docs/setup.md). The dialect's own knowledge (its
default diameter programming, its settable work offsets, its variable names) comes from its registry entry
(interp.DIALECTS)."""
from __future__ import annotations

import os
import re
from dataclasses import dataclass

from cutsim.base.specs import MachineSpec
from cutsim.interp import DIALECTS
from cutsim.interp.errors import CutsimError

from .limits import (ACCELERATION_MAX, AXIS_KINDS, COORD_MAX, EXTERNAL_NAME_MAX, FUNCTION_MAX, RATE_MAX, STRING_MAX, TRANSFORMATIONS,
                     VALUE_MAX, is_coord, is_number, show)
from .reader import Locator, Reader

KINDS = ("lathe", "mill")
# a subprogram, cycle file or G code the machine has: letters, digits, _ . - (0_INICIO_PROG.NC, G803, L_VENDOR)
_EXTERNAL_NAME = re.compile(r"[A-Z0-9_][A-Z0-9_.\-]*")
# extra axis names: A B C U V W, optionally with a number (A1, C2), or two or three letters with a
# number (SP1; Sinumerik channel axis names, written NAME=value in the program). X, Y, Z are the machine's own.
_AXIS_NAME = re.compile(r"[ABCUVW][0-9]{0,2}|[A-Z]{2,3}[0-9]{1,2}")


@dataclass
class Machine:
    """What the [machine] table says: the MachineSpec and the setup's own machine lists."""

    spec: MachineSpec
    constants: dict[int, float]
    axes: dict[str, str]
    m_functions: frozenset[int]
    h_functions: frozenset[int]
    transformations: frozenset[str]
    subprogram_path: tuple[str, ...]
    external_subprograms: frozenset[str]
    tool_table: str = ""  # rs274ngc: LinuxCNC's .tbl, absolute path or ""
    parameter_file: str = ""  # rs274ngc: LinuxCNC's .var, absolute path or ""
    thread_acceleration: float = 0.0  # sinumerik lathe: the thread axis' acceleration (mm/s^2; 0: not given)


def read_machine(loc: Locator, table: dict) -> Machine:
    """The [machine] table, checked key by key in the order the docs list them."""
    m = Reader(loc, table, "machine")
    kind = m.get("kind", str, check=lambda v: v in KINDS, why=f"must be one of {', '.join(KINDS)}")
    dialect = m.get("dialect", str, check=lambda v: v in DIALECTS, why=f"must be one of {', '.join(DIALECTS)}")
    # when the setup does not say: the registry's default on a lathe (interp.DIALECTS), radii on a mill
    diam = m.get("diameter_programming", bool, DIALECTS[dialect].diameter_programming if kind == "lathe" else False)
    m03 = m.get("m03", str, "positive", check=lambda v: v in ("positive", "negative"), why="must be positive or negative")
    start = m.get("start", list, None)
    if start is not None:
        if len(start) != 3 or not all(is_number(c) for c in start):
            raise m.fail("start", f"must be three finite numbers [x, y, z], not {show(start)}")
        if not all(is_coord(c) for c in start):
            raise m.fail("start", f"must lie within -{COORD_MAX:g} to {COORD_MAX:g}, not {show(start)}")
        start = tuple(float(c) for c in start)
    rate = dict(check=lambda v: 0 < v <= RATE_MAX, why=f"must be more than 0 and at most {RATE_MAX:g} mm/min")
    rapid = m.get("rapid", float, 10000.0, **rate)
    feed = m.get("feed", float, 100.0, **rate)
    accel = m.get("thread_acceleration", float, 0.0, check=lambda v: 0 < v <= ACCELERATION_MAX,
                  why=f"must be more than 0 and at most {ACCELERATION_MAX:,.0f} mm/s^2")
    if accel and (kind, dialect) != ("lathe", "sinumerik"):
        raise m.fail("thread_acceleration", "is the acceleration a Sinumerik lathe's thread axis runs its DITS/DITE "
                                            "= -1 ramps at: only for kind = \"lathe\", dialect = \"sinumerik\"")
    constants = {}
    consts = m.get("constants", dict, {})
    for k, v in consts.items():
        if not re.fullmatch(r"\d{1,6}", k):
            raise Reader(loc, consts, "machine.constants").fail(k, "constant names are numbers (0 to 999999)")
        c = Reader(loc, consts, "machine.constants")
        constants[int(k)] = c.get(k, float, check=lambda v: abs(v) <= VALUE_MAX,
                                  why=f"must lie within -{VALUE_MAX:g} to {VALUE_MAX:g}")
    axes = _axes(loc, m)
    m_functions = _functions(m, "m_functions", "M")
    h_functions = _functions(m, "h_functions", "H")
    transformations = _transformations(m)
    subprogram_path = _subprogram_path(loc, m)
    external_subprograms = _external_subprograms(m)
    linuxcnc = {key: _linuxcnc_file(loc, m, key, dialect) for key in ("tool_table", "parameter_file")}
    m.done()
    return Machine(MachineSpec(kind, dialect, diam, m03, start, rapid, feed), constants, axes, m_functions,
                   h_functions, transformations, subprogram_path, external_subprograms, **linuxcnc,
                   thread_acceleration=accel)


def read_parameters(loc: Locator, table: dict) -> dict[int, float]:
    """[parameters] R04 = 2.5: the R parameters' values before the program starts."""
    params = {}
    p = Reader(loc, table, "parameters")
    for k in table:
        if not re.fullmatch(r"R\d{1,3}", k):
            raise p.fail(k, "parameter names are R followed by a number (R04)")
        params[int(k[1:])] = p.get(k, float, check=lambda v: abs(v) <= VALUE_MAX,
                                   why=f"must lie within -{VALUE_MAX:g} to {VALUE_MAX:g}")
    return params


def _axes(loc: Locator, m: Reader) -> dict[str, str]:
    """[machine] axes = { A = "rotary", W = "linear" }: the machine's extra axes."""
    table = m.get("axes", dict, {})
    r = Reader(loc, table, "machine.axes")
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


def _functions(m: Reader, key: str, letter: str) -> frozenset[int]:
    """[machine] m_functions / h_functions = [20, 70]: machine functions that pass silently."""
    v = m.get(key, list, [])
    for k, c in enumerate(v):
        if isinstance(c, str) and re.fullmatch(rf"\s*{letter}\s*0*\d{{1,5}}\s*", c, re.I):
            raise m.fail_at(key, (k,), f"write {c.strip()!r} as the number {int(c.strip()[1:])}")
        if not isinstance(c, int) or isinstance(c, bool) or not 0 <= c <= FUNCTION_MAX:
            raise m.fail_at(key, (k,), f"an {letter} function is a whole number from 0 to {FUNCTION_MAX}, "
                                       f"not {show(c)}")
    return frozenset(v)


def _transformations(m: Reader) -> frozenset[str]:
    """[machine] transformations = ["TRAFO"]: kinematic transformations under which the program's
    coordinates are the workpiece's Cartesian coordinates (ISG #TRAFO ON on a gantry or robot)."""
    v = m.get("transformations", list, [])
    for k, c in enumerate(v):
        if not isinstance(c, str) or c.strip().upper() not in TRANSFORMATIONS:
            raise m.fail_at("transformations", (k,), f"a transformation is one of {', '.join(TRANSFORMATIONS)}, "
                                                      f"not {show(c)}")
    return frozenset(c.strip().upper() for c in v)


def _subprogram_path(loc: Locator, m: Reader) -> tuple[str, ...]:
    """[machine] subprogram_path = ["subs", ...]: folders searched for subprograms after the
    program's own, relative to the setup file's folder; each must exist."""
    v = m.get("subprogram_path", list, [])
    base = os.path.dirname(os.path.abspath(loc.path))
    out: list[str] = []
    for k, d in enumerate(v):
        if not isinstance(d, str) or not d.strip():
            raise m.fail_at("subprogram_path", (k,), f"a folder is a non-empty string, not {show(d)}")
        path = os.path.normpath(os.path.join(base, d))
        if not os.path.isdir(path):
            raise m.fail_at("subprogram_path", (k,), f"no such folder: {path}")
        if path not in out:
            out.append(path)
    return tuple(out)


def _linuxcnc_file(loc: Locator, m: Reader, key: str, dialect: str) -> str:
    """[machine] tool_table = "tools.tbl" / parameter_file = "params.var": LinuxCNC's files,
    relative to the setup file's folder; read by the rs274ngc dialect only."""
    v = m.get(key, str, "")
    if not v:
        return ""
    if dialect != "rs274ngc":
        raise m.fail(key, f"only the rs274ngc dialect reads a LinuxCNC {key.replace('_', ' ')}")
    path = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(loc.path)), v))
    if not os.path.isfile(path):
        raise m.fail(key, f"no such file: {path}")
    return path


def _external_subprograms(m: Reader) -> frozenset[str]:
    """[machine] external_subprograms = ["0_Inicio_Prog.nc", "G803", "L_VENDOR"]: subprograms,
    cycle files and implicit-call G codes the machine has but the simulator does not (vendor
    cycles whose source the user does not have). Each is kept as its file name (the part after
    the last / or \\), upper-cased; a name given twice (in any case or folder) is an error."""
    key = "external_subprograms"
    v = m.get(key, list, [])
    out: dict[str, int] = {}
    for k, c in enumerate(v):
        if not isinstance(c, str) or not c.strip():
            raise m.fail_at(key, (k,), f"a subprogram is a non-empty string (its name or file name), not {show(c)}")
        name = re.split(r"[/\\]", c.strip())[-1].strip().upper()
        if not name:
            raise m.fail_at(key, (k,), f"{show(c)} is a folder: name the subprogram's file")
        if len(name) > EXTERNAL_NAME_MAX:
            raise m.fail_at(key, (k,), f"a subprogram name has at most {EXTERNAL_NAME_MAX} characters "
                                       f"(got {len(name)})")
        if not _EXTERNAL_NAME.fullmatch(name):
            raise m.fail_at(key, (k,), f"{show(c)}: a subprogram name is letters, digits, _ . and - "
                                       "(L_VENDOR, G803, 0_Inicio_Prog.nc), not starting with . or -")
        if name in out:
            raise m.fail_at(key, (k,), f"{name} is given twice (also element {out[name] + 1})")
        out[name] = k
    return frozenset(out)


def read_variables(loc: Locator, table: dict, dialect: str) -> dict[str, float | str]:
    """[variables]: values of system variables, PLC data, machine data and global user data the
    program reads. Names upper-cased, spaces inside [] removed; an unquoted dotted ISG name
    (V.G.X = 1, a nested table to TOML) is joined back with dots. Which names a dialect accepts
    comes from its registry entry (interp.VariableNames)."""
    names = DIALECTS[dialect].variables
    out: dict[str, float | str] = {}

    todo: list[tuple[tuple, object]] = [((k,), v) for k, v in reversed(table.items())]
    while todo:  # depth first, in the order written (no recursion: a dotted key may have any depth)
        here, v = todo.pop()
        if isinstance(v, dict):
            todo.extend((here + (k,), w) for k, w in reversed(v.items()))
            continue
        written = ".".join(here)
        at = loc.at(("variables",) + here)
        head = f"[variables] {written if len(written) <= 60 else written[:57] + '...'}: "

        def fail(message):
            return CutsimError(loc.path, *at, head + message)

        name = re.sub(r"\[[^\]]*\]", lambda mt: re.sub(r"\s+", "", mt.group()), written.strip().upper())
        if not names.matches(name):
            raise fail(names.accepts)
        if re.fullmatch(r"R[0-9]+", name):
            raise fail(f"R parameters are set in [parameters] ({name} = ...)")
        if name in out:
            raise fail(f"{name} is given twice")
        if isinstance(v, bool):
            out[name] = 1.0 if v else 0.0
        elif isinstance(v, (int, float)):
            if not is_number(v) or abs(v) > VALUE_MAX:
                raise fail(f"must be a finite number within -{VALUE_MAX:g} to {VALUE_MAX:g}, not {show(v)}")
            out[name] = float(v)
        elif isinstance(v, str):
            if len(v) > STRING_MAX:
                raise fail(f"a string value has at most {STRING_MAX} characters (got {len(v)})")
            out[name] = v
        else:
            raise fail(f"must be a number, a string or true/false, not {show(v)}")
    return dict(sorted(out.items()))


def read_work_offsets(loc: Locator, table: dict, dialect: str) -> dict[str, tuple[float, float, float]]:
    """[work_offsets] G54 = [x, y, z]: the settable work offsets (mm) the program selects."""
    r = Reader(loc, table, "work_offsets")
    offsets = DIALECTS[dialect].work_offsets  # the dialect's settable offsets (interp.WorkOffsets)
    known = offsets.known
    not_settable = dict(offsets.not_settable)
    out: dict[str, tuple[float, float, float]] = {}
    for k in table:
        name = k.strip().upper()
        if name in ("G500", "G53", "G153", "SUPA"):
            raise r.fail(k, f"{name} is no work offset (it switches the settable offsets off); "
                            f"the offsets are {known}")
        if name in not_settable:
            raise r.fail(k, f"{not_settable[name]}; the settable offsets are {known}")
        if name == "G92":
            raise r.fail(k, "G92 is set by the program, not the setup")
        if name not in offsets.names:
            raise r.fail(k, f"the work offsets of {dialect} are {known}")
        if name in out:
            raise r.fail(k, f"{name} is given twice")
        v = r.get(k, list)
        if len(v) != 3 or not all(is_number(c) for c in v):
            raise r.fail(k, f"must be three finite numbers [x, y, z], not {show(v)}")
        if not all(is_coord(c) for c in v):
            raise r.fail(k, f"must lie within -{COORD_MAX:g} to {COORD_MAX:g} mm, not {show(v)}")
        out[name] = (float(v[0]), float(v[1]), float(v[2]))
    return dict(sorted(out.items(), key=lambda kv: int(kv[0][1:])))
