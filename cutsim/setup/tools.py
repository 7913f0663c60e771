"""The [[tool]] tables: lathe tools (thread, turning, grooving, profile; centre drill and tap on the
spindle axis) and mill tools (endmill, ballmill, drill), their numbers and names (docs/setup.md). Types are checked here; ranges in stock/tools.py,
shared with tools built in Python."""
from __future__ import annotations

from cutsim.base.specs import ToolSpec
from cutsim.interp.errors import CutsimError

from .reader import Locator, Reader

TOOL_KEYS = {
    "thread": {"angle", "tip_radius", "height", "thickness", "side", "form", "pitch", "crest_radius", "bar_diameter",
               "bar_reach", "shank", "hand"},
    "turning": {"angle", "tip_radius", "height", "thickness", "side", "insert", "size", "approach", "hand",
                "bar_diameter", "bar_reach", "shank"},
    "grooving": {"width", "corner_radius", "height", "thickness", "side", "hand", "bar_diameter", "bar_reach",
                 "shank"},
    "profile": {"points", "thickness"},
    "endmill": {"diameter", "length", "corner_radius", "center_cutting"},
    "ballmill": {"diameter", "length"},
    "drill": {"diameter", "length", "point_angle"},
    "centredrill": {"diameter", "pilot_length", "body_diameter", "countersink", "point_angle", "length"},
    "tap": {"diameter", "pitch", "length", "chamfer"},
}
TOOL_COMMON = {"number", "kind", "name"}  # keys of every [[tool]]
TOOL_NAME_MAX = 32  # characters (a Sinumerik tool name is a STRING[32])
DRILL_LENGTH_FACTOR = 10.0  # a drill's default length: 10 x its diameter (a jobber drill's flutes)


def read_tools(loc: Locator, raw_tools, kind: str) -> tuple[list[ToolSpec], dict[str, int]]:
    """The [[tool]] tables of a ``kind`` machine: the tools, and their names (as written) -> numbers.
    Numbers and names (case-insensitive) are unique; each tool must fit the machine."""
    if not isinstance(raw_tools, list):
        raise CutsimError(loc.path, *loc.locate("tool", None, None), "tools are written [[tool]] (an array of tables)")
    tools = []
    numbers = set()
    tool_names: dict[str, int] = {}
    folded: dict[str, str] = {}  # casefolded name -> the name as first written
    for i, t in enumerate(raw_tools):
        tool = read_tool(loc, Reader(loc, t, "tool", i), i)
        if tool.number in numbers:
            raise Reader(loc, t, "tool", i).fail("number", f"tool {tool.number} is defined twice")
        numbers.add(tool.number)
        if tool.name:
            other = folded.get(tool.name.casefold())
            if other is not None:
                same = "names" if other == tool.name else f"differs only in case from {other!r}, which names"
                raise Reader(loc, t, "tool", i).fail(
                    "name", f"{tool.name!r} {same} tool {tool_names[other]} already")
            folded[tool.name.casefold()] = tool.name
            tool_names[tool.name] = tool.number
        tools.append(tool)
    if not tools:
        raise CutsimError(loc.path, 1, 1, "the setup needs at least one [[tool]]")
    for t in tools:
        on_lathe = t.is_lathe_tool or t.kind == "drill"  # a drill works on a lathe's spindle axis too
        if kind == "lathe" and not on_lathe or kind == "mill" and t.is_lathe_tool:
            i = tools.index(t)
            raise Reader(loc, raw_tools[i], "tool", i).fail("kind", f"a {t.kind} tool does not fit a {kind}")
    return tools, tool_names


def read_tool(loc: Locator, t: Reader, i: int) -> ToolSpec:
    """One [[tool]] table (the ``i``-th)."""
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
        kw.update(_lathe_keys(t, kind))
    if kind == "grooving":
        kw["width"] = t.get("width", float, 3.0)
        kw["corner_radius"] = t.get("corner_radius", float, 0.2)
        kw["height"] = t.get("height", float, 10.0)
    if kind in ("thread", "turning", "grooving"):
        kw["side"] = t.get("side", str, "outside")
        kw["bar_diameter"] = t.get("bar_diameter", float, 0.0)
        kw["bar_reach"] = t.get("bar_reach", float, 0.0)
        kw["hand"] = t.get("hand", str, "R")  # a thread insert is neutral: its hand places its holder only
        # an outside or face tool's holder (0: none); an inside tool's body is its boring bar
        from cutsim.stock.inserts import default_shank

        shank = 0.0 if kw["side"] == "inside" else default_shank(kind, kw.get("insert", ""), kw.get("size", 0.0),
                                                                   kw.get("width", 0.0))
        kw["shank"] = t.get("shank", float, shank)
    if kind == "profile":
        kw["points"] = t.points("points")
    if kind in LATHE_KINDS:
        kw["thickness"] = t.get("thickness", float, 5.0)
    if kind in ("endmill", "ballmill"):
        kw["diameter"] = t.get("diameter", float)
        kw["length"] = t.get("length", float, min(4.0 * kw["diameter"], SIZE_MAX))
        if kind == "endmill":
            kw["corner_radius"] = t.get("corner_radius", float, 0.0)
            kw["center_cutting"] = t.get("center_cutting", bool, True)
        else:
            kw["corner_radius"] = kw["diameter"] / 2
    if kind in ("centredrill", "tap"):
        kw.update(_axial_keys(t, kind))
    if kind == "drill":
        kw["diameter"] = t.get("diameter", float)
        kw["length"] = t.get("length", float, min(DRILL_LENGTH_FACTOR * kw["diameter"], SIZE_MAX))
        kw["point_angle"] = t.get("point_angle", float, 118.0)
    t.done()
    line, col = loc.locate("tool", None, i)
    spec = ToolSpec(number, kind, **kw, name=name, source=loc.path, line=line, col=col)
    bad = tool_problem(spec)
    if bad is not None:
        key, why = bad
        raise t.fail(key, why)  # at the key's line, or the table's when the key is a default
    return spec



LATHE_KINDS = ("thread", "turning", "grooving", "profile")


def _lathe_keys(t: Reader, kind: str) -> dict:
    """The V (``angle``, ``tip_radius``, ``height``) of a thread or turning tool, or what replaces
    it: an ISO insert (``insert``, ``size``, ``approach``), a full-profile thread insert (``form``,
    ``pitch``). The angle of an insert is its shape's: writing one is an error."""
    kw: dict = {}
    insert = t.get("insert", str, "") if kind == "turning" else ""
    form = t.get("form", str, "partial") if kind == "thread" else "partial"
    if insert:
        if "angle" in t.table or "height" in t.table:
            key = "angle" if "angle" in t.table else "height"
            raise t.fail(key, f"an ISO insert's shape gives its angle and size: {key} is for the plain V "
                              "(insert not given)")
        kw["insert"], kw["size"] = insert, t.get("size", float, 12.7)
        kw["approach"] = t.get("approach", float, 0.0)
    elif "size" in t.table or "approach" in t.table:
        key = "size" if "size" in t.table else "approach"
        raise t.fail(key, "is a key of an ISO insert: give its shape (insert = \"C\", ...)")
    if form != "partial":
        kw["form"], kw["pitch"] = form, t.get("pitch", float)
        kw["crest_radius"] = t.get("crest_radius", float, 0.0)
    elif "pitch" in t.table or "crest_radius" in t.table:
        key = "pitch" if "pitch" in t.table else "crest_radius"
        raise t.fail(key, 'is a key of a full-profile insert (form = "full")')
    kw["angle"] = t.get("angle", float, 60.0 if kind == "thread" else 55.0)
    kw["tip_radius"] = t.get("tip_radius", float, 0.0 if kind == "thread" else 0.4)
    kw["height"] = t.get("height", float, 10.0)
    return kw


# DIN 333 form A proportions: body ~ 2.5 x pilot, pilot ~ 1.2 x its diameter long; a tap's chamfer of
# 3 pitches (form C, for blind holes) and a thread length of 2 x its diameter
CENTRE_BODY_FACTOR, CENTRE_PILOT_FACTOR, CENTRE_LENGTH_FACTOR = 2.5, 1.2, 6.0
TAP_CHAMFER_PITCHES, TAP_LENGTH_FACTOR = 3.0, 2.0


def _axial_keys(t: Reader, kind: str) -> dict:
    """A centre drill's or a tap's keys with their defaults (docs/setup.md)."""
    kw: dict = {"diameter": t.get("diameter", float)}
    d = kw["diameter"]
    if kind == "centredrill":
        kw["body_diameter"] = t.get("body_diameter", float, CENTRE_BODY_FACTOR * d)
        kw["pilot_length"] = t.get("pilot_length", float, CENTRE_PILOT_FACTOR * d)
        kw["countersink"] = t.get("countersink", float, 60.0)
        kw["point_angle"] = t.get("point_angle", float, 118.0)
        kw["length"] = t.get("length", float, CENTRE_LENGTH_FACTOR * kw["body_diameter"])
    else:
        kw["pitch"] = t.get("pitch", float)
        kw["chamfer"] = t.get("chamfer", float, TAP_CHAMFER_PITCHES * kw["pitch"])
        kw["length"] = t.get("length", float, TAP_LENGTH_FACTOR * d)
    return kw


def _tool_name_ok(v: str) -> bool:
    return (0 < len(v) <= TOOL_NAME_MAX and v == v.strip() and '"' not in v
            and all(c.isprintable() for c in v))

