"""The [[check]] tables (docs/checks.md): each is a plain dict spec that cutsim.reports.checks
evaluates on the finished part; keys by kind in CHECK_KEYS."""
from __future__ import annotations

import os

from cutsim.interp.errors import CutsimError

from .limits import is_number, show
from .reader import Locator, Reader

# [[check]] kinds and their keys besides kind and name (docs/checks.md)
CHECK_KEYS = {
    "diameter": {"z", "expected", "tolerance", "angles"},
    "thread": {"z", "lead", "starts", "hand", "root_diameter", "phase", "phase_z", "tolerance", "lead_tolerance",
               "phase_tolerance", "angles", "side", "major_diameter", "minor_diameter", "pitch_diameter",
               "wire_diameter", "designation"},
    "ramp": {"z", "radius", "diameter", "tolerance", "step"},
    "slot": {"at", "direction", "width", "floor", "center", "z", "tolerance"},
    "pocket": {"at", "size", "floor", "center", "z", "tolerance"},
    "depth": {"at", "z", "tolerance"},
    "bore": {"z", "face", "diameter", "depth", "tip_depth", "tolerance"},
    "groove": {"at", "side", "width", "depth", "diameter", "center", "reach", "tolerance"},
    "shoulder": {"diameter", "z", "range", "side", "tolerance"},
    "volume": {"removed", "tolerance"},
    "design": {"path", "max_gouge", "max_excess", "max_deviation"},
}
LATHE_CHECKS = ("diameter", "thread", "ramp", "bore", "groove", "shoulder")
MILL_CHECKS = ("slot", "pocket", "depth")
_POS = dict(check=lambda v: v > 0, why="must be positive")
_NONNEG = dict(check=lambda v: v >= 0, why="must not be negative")


def read_checks(loc: Locator, raw_checks, machine_kind: str) -> list[dict]:
    """The [[check]] tables of a ``machine_kind`` machine; names are unique."""
    if not isinstance(raw_checks, list):
        raise CutsimError(loc.path, *loc.locate("check", None, None), "checks are written [[check]] (an array of tables)")
    checks = [read_check(loc, Reader(loc, c, "check", i), i, machine_kind) for i, c in enumerate(raw_checks)]
    names = [c["name"] for c in checks]
    for i, c in enumerate(checks):
        if names.index(c["name"]) != i:
            raise Reader(loc, raw_checks[i], "check", i).fail("name", f"{c['name']!r} names two checks")
    return checks


def check_spec(table: dict, machine_kind: str) -> dict:
    """A check given in Python (cutsim.testing, Result.check) as a [[check]] table, validated the
    same way; errors name ``<check>``."""
    loc = Locator("<check>", "")
    return read_check(loc, Reader(loc, table, "check", 0), 0, machine_kind)


def read_check(loc: Locator, c: Reader, i: int, machine_kind: str) -> dict:
    """One [[check]] table (the ``i``-th) as a plain dict (see docs/checks.md)."""
    kind = c.get("kind", str, check=lambda v: v in CHECK_KEYS, why=f"must be one of {', '.join(CHECK_KEYS)}")
    if kind in LATHE_CHECKS and machine_kind != "lathe" or kind in MILL_CHECKS and machine_kind != "mill":
        raise c.fail("kind", f"a {kind} check needs a {'lathe' if kind in LATHE_CHECKS else 'mill'}")
    allowed = CHECK_KEYS[kind] | {"kind", "name"}
    for k in c.table:
        if k not in allowed:
            raise c.fail(k, f"unknown key for a {kind} check (known: {', '.join(sorted(allowed - {'kind'}))})")
    line, _col = loc.locate("check", None, i)
    spec: dict = {"kind": kind, "name": c.get("name", str, f"{kind} #{i + 1}", check=lambda v: v.strip() != "",
                                              why="must not be empty"), "index": i, "line": line}
    _KINDS[kind](loc, c, i, spec)
    c.done()
    return spec


def _xy(c: Reader, key: str, default=...):
    v = c.get(key, list, default)
    if v is default:
        return v
    if len(v) != 2 or not all(is_number(q) for q in v):
        raise c.fail(key, f"must be two numbers [x, y], not {show(v)}")
    return (float(v[0]), float(v[1]))


def _diameter(loc: Locator, c: Reader, i: int, spec: dict) -> None:
    spec["z"] = c.get("z", float)
    spec["expected"] = c.get("expected", float, **_POS)
    spec["tolerance"] = c.get("tolerance", float, 0.02, **_NONNEG)
    spec["angles"] = c.get("angles", int, 72, check=lambda v: 4 <= v <= 3600, why="must be 4 to 3600")


def _thread(loc: Locator, c: Reader, i: int, spec: dict) -> None:
    spec["z"] = c.pair("z")
    spec["starts"] = c.get("starts", int, 1, check=lambda v: 1 <= v <= 16, why="must be 1 to 16")
    _gauge(c, spec)
    if spec["limits"] is not None:
        spec["lead"] = c.get("lead", float, spec["limits"]["pitch"] * spec["starts"], **_POS)
        if abs(spec["lead"] / spec["starts"] - spec["limits"]["pitch"]) > 1e-9:
            raise c.fail("designation", f"the pitch of {spec['designation']} is not lead / starts = "
                                        f"{spec['lead'] / spec['starts']:g} mm")
    else:
        spec["lead"] = c.get("lead", float, **_POS)
    spec["hand"] = c.get("hand", str, "right", check=lambda v: v in ("right", "left"), why="must be right or left")
    spec["root_diameter"] = c.get("root_diameter", float, None, **_POS)
    spec["tolerance"] = c.get("tolerance", float, 0.02, **_NONNEG)
    spec["lead_tolerance"] = c.get("lead_tolerance", float, 0.005, **_NONNEG)
    spec["phase_tolerance"] = c.get("phase_tolerance", float, 2.0, **_NONNEG)
    spec["angles"] = c.get("angles", int, 36, check=lambda v: 8 <= v <= 720, why="must be 8 to 720")
    phase = c.get("phase", list, None)
    if phase is not None:
        if not all(is_number(q) for q in phase):
            raise c.fail("phase", f"must be a list of angles in degrees, not {show(phase)}")
        if len(phase) != spec["starts"]:
            raise c.fail("phase", f"needs one angle per start ({spec['starts']}), got {len(phase)}")
        spec["phase"] = [float(q) for q in phase]
        spec["phase_z"] = c.get("phase_z", float)
    else:
        spec["phase"] = None
        if "phase_z" in c.table:
            raise c.fail("phase_z", "is only used with phase")


def _gauge(c: Reader, spec: dict) -> None:
    """The thread gauge keys: side, major/minor/pitch diameters, wire_diameter, designation
    (ISO 965-1 limits, cutsim.reports.iso965); the designation's position letter sets the side."""
    from cutsim.reports.iso965 import DesignationError, limits

    spec["designation"] = c.get("designation", str, None)
    spec["limits"] = None
    if spec["designation"] is not None:
        try:
            spec["limits"] = limits(spec["designation"])
        except DesignationError as e:
            raise c.fail("designation", str(e)) from None
    side = "inside" if spec["limits"] and spec["limits"]["inside"] else "outside"
    spec["side"] = c.get("side", str, side, check=lambda v: v in ("outside", "inside"), why="must be outside or inside")
    if spec["limits"] is not None and spec["side"] != side:
        raise c.fail("side", f"{spec['designation']} is an {side} thread")
    for k in ("major_diameter", "minor_diameter", "pitch_diameter", "wire_diameter"):
        spec[k] = c.get(k, float, None, **_POS)


def _ramp(loc: Locator, c: Reader, i: int, spec: dict) -> None:
    spec["z"] = c.pair("z")
    has_r, has_d = "radius" in c.table, "diameter" in c.table
    if has_r == has_d:
        raise c.fail(None, "a ramp check needs exactly one of radius = [r1, r2] or diameter = [d1, d2]")
    if has_r:
        spec["radius"] = c.pair("radius", increasing=False)
    else:
        d = c.pair("diameter", increasing=False)
        spec["radius"] = (d[0] / 2, d[1] / 2)
    spec["tolerance"] = c.get("tolerance", float, 0.02, **_NONNEG)
    spec["step"] = c.get("step", float, 0.1, **_POS)


def _at_least_one(c: Reader, spec: dict, keys: tuple[str, ...]) -> None:
    if all(spec[k] is None for k in keys):
        raise c.fail(None, f"a {spec['kind']} check needs at least one of {', '.join(keys)}")


def _bore(loc: Locator, c: Reader, i: int, spec: dict) -> None:
    spec["face"] = c.get("face", float, 0.0)
    spec["z"] = c.get("z", float, None)
    spec["diameter"] = c.get("diameter", float, None, **_POS)
    spec["depth"] = c.get("depth", float, None, **_POS)
    spec["tip_depth"] = c.get("tip_depth", float, None, **_POS)
    spec["tolerance"] = c.get("tolerance", float, 0.02, **_NONNEG)
    _at_least_one(c, spec, ("diameter", "depth", "tip_depth"))
    if spec["z"] is None:
        if spec["depth"] is None:
            raise c.fail("z", "is required without depth (the height where the diameter is measured)")
        spec["z"] = spec["face"] - spec["depth"] / 2.0
    elif spec["z"] >= spec["face"]:
        raise c.fail("z", f"must lie below the face at {spec['face']:g}")


def _side(c: Reader) -> str:
    return c.get("side", str, "outside", check=lambda v: v in ("outside", "inside"), why="must be outside or inside")


def _groove(loc: Locator, c: Reader, i: int, spec: dict) -> None:
    spec["at"] = c.get("at", float)
    spec["side"] = _side(c)
    for k in ("width", "depth", "diameter"):
        spec[k] = c.get(k, float, None, **_POS)
    spec["center"] = c.get("center", float, None)
    spec["reach"] = c.get("reach", float, 10.0, **_POS)
    spec["tolerance"] = c.get("tolerance", float, 0.02, **_NONNEG)
    _at_least_one(c, spec, ("width", "depth", "diameter", "center"))


def _shoulder(loc: Locator, c: Reader, i: int, spec: dict) -> None:
    spec["diameter"] = c.get("diameter", float, **_POS)
    spec["expected"] = c.get("z", float)
    spec["range"] = c.pair("range", (spec["expected"] - 5.0, spec["expected"] + 5.0))
    spec["side"] = _side(c)
    spec["tolerance"] = c.get("tolerance", float, 0.02, **_NONNEG)


def _slot_or_pocket(loc: Locator, c: Reader, i: int, spec: dict) -> None:
    kind = spec["kind"]
    spec["at"] = _xy(c, "at")
    spec["floor"] = c.get("floor", float, None)
    spec["z"] = c.get("z", float, None)
    spec["tolerance"] = c.get("tolerance", float, 0.02, **_NONNEG)
    if kind == "slot":
        spec["direction"] = c.get("direction", str, check=lambda v: v in ("x", "y"), why="must be x or y")
        spec["width"] = c.get("width", float, None, **_POS)
        spec["center"] = c.get("center", float, None)
        wanted = ("width", "floor", "center")
    else:
        spec["size"] = c.pair("size", None, increasing=False)
        if spec["size"] is not None and min(spec["size"]) <= 0:
            raise c.fail("size", "widths must be positive")
        spec["center"] = _xy(c, "center", None)
        wanted = ("size", "floor", "center")
    if all(spec[k] is None for k in wanted):
        raise c.fail(None, f"a {kind} check needs at least one of {', '.join(wanted)}")


def _depth(loc: Locator, c: Reader, i: int, spec: dict) -> None:
    spec["at"] = _xy(c, "at")
    spec["expected"] = c.get("z", float)
    spec["tolerance"] = c.get("tolerance", float, 0.02, **_NONNEG)


def _volume(loc: Locator, c: Reader, i: int, spec: dict) -> None:
    spec["removed"] = c.get("removed", float, **_NONNEG)
    spec["tolerance"] = c.get("tolerance", float, None, **_NONNEG)


def _design(loc: Locator, c: Reader, i: int, spec: dict) -> None:
    rel = c.get("path", str)
    path = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(loc.path)), rel))
    if not os.path.isfile(path):
        raise c.fail("path", f"no such file: {path}")
    spec["path"] = path
    spec["max_gouge"] = c.get("max_gouge", float, 0.01, **_NONNEG)
    spec["max_excess"] = c.get("max_excess", float, None, **_NONNEG)
    spec["max_deviation"] = c.get("max_deviation", float, None, **_NONNEG)
    spec["column"] = loc.locate("check", "path", i)[1]
    spec["path_line"] = loc.locate("check", "path", i)[0]


_KINDS = {"diameter": _diameter, "thread": _thread, "ramp": _ramp, "bore": _bore, "groove": _groove,
          "shoulder": _shoulder, "slot": _slot_or_pocket,
          "pocket": _slot_or_pocket, "depth": _depth, "volume": _volume, "design": _design}
