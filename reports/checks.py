"""Evaluate ``[[check]]`` specs on a simulated part: pure functions, spec dict + Result -> record.

A record (one per check, in report.json under "checks")::

    {"name": "thread M27", "kind": "thread", "line": 12, "passed": false,
     "items": [{"quantity": "root_diameter", "expected": 26.177, "measured": 26.277,
                "tolerance": 0.02, "unit": "mm", "passed": false}, ...],
     "details": {...}}

A check passes when every item passes. Specs come validated from cutsim/setup.py (see
docs/checks.md for every kind and key).
"""
from __future__ import annotations

import math

import numpy as np

from . import measure as M
from . import threads as T
from . import turned

KINDS = ("diameter", "thread", "ramp", "bore", "groove", "shoulder", "slot", "pocket", "depth", "volume", "design")


def _r(v, nd: int = 6):
    if v is None:
        return None
    if isinstance(v, (list, tuple)):
        return [_r(x, nd) for x in v]
    if isinstance(v, str):
        return v
    if isinstance(v, (bool, np.bool_)):
        return bool(v)
    if isinstance(v, (int, np.integer)):
        return int(v)
    f = float(v)
    if not math.isfinite(f):  # a measurement that found nothing to measure (NaN): not measured
        return None
    f = round(f, nd)
    return 0.0 if f == 0 else f


def item(quantity: str, expected, measured, tolerance, unit: str = "mm", passed: bool | None = None) -> dict:
    """One compared quantity. Numbers pass when |measured - expected| <= tolerance; anything else
    passes when equal. A missing measurement (None) fails."""
    if passed is None:
        if measured is None or (isinstance(measured, float) and not math.isfinite(measured)):
            passed = False
        elif isinstance(expected, (int, float)) and not isinstance(expected, bool) and tolerance is not None:
            passed = abs(float(measured) - float(expected)) <= float(tolerance) + 1e-12
        else:
            passed = measured == expected
    if isinstance(measured, float) and not math.isfinite(measured):
        measured = None
    return {"quantity": quantity, "expected": _r(expected), "measured": _r(measured), "tolerance": _r(tolerance),
            "unit": unit, "passed": bool(passed)}


def _record(spec: dict, items: list[dict], details: dict | None = None) -> dict:
    return {"name": spec["name"], "kind": spec["kind"], "line": spec.get("line", 0),
            "passed": bool(items) and all(i["passed"] for i in items), "items": items, "details": details or {}}


# ----------------------------------------------------------------------------------------------
def check_diameter(spec: dict, result) -> dict:
    d = M.diameters_at(result.part, spec["z"], spec["angles"])
    ok = d[np.isfinite(d)]
    lo = float(ok.min()) if len(ok) == len(d) and len(d) else None
    hi = float(ok.max()) if len(ok) == len(d) and len(d) else None
    tol = spec["tolerance"]
    return _record(spec, [item("diameter_min", spec["expected"], lo, tol),
                          item("diameter_max", spec["expected"], hi, tol)],
                   {"z": spec["z"], "angles": spec["angles"]})


GAUGED = ("major_diameter", "minor_diameter", "pitch_diameter")


def limit_item(quantity: str, low, high, measured) -> dict:
    """An item that passes when ``measured`` lies within [low, high] (either may be None: no
    limit on that side); ``expected`` reads the limits as text, ``limits`` holds them."""
    ok = measured is not None and math.isfinite(measured) and (low is None or measured >= low - 1e-12) \
        and (high is None or measured <= high + 1e-12)
    text = (f"{low:.3f} to {high:.3f}" if low is not None and high is not None
            else f"min {low:.3f}" if low is not None else f"max {high:.3f}")
    it = item(quantity, text, measured, None, passed=ok)
    it["limits"] = [_r(low), _r(high)]
    return it


def _gauge_items(spec: dict, part) -> tuple[list[dict], dict]:
    """Major, minor and pitch diameter items (expected values or the designation's limits)."""
    lim = spec.get("limits")
    wanted = [k for k in GAUGED if spec.get(k) is not None or lim is not None]
    if not wanted:
        return [], {}
    inside = spec.get("side") == "inside"
    g = T.gauge_part(part, spec["z"][0], spec["z"][1], spec["lead"] / spec["starts"], inside, spec["angles"],
                     spec.get("wire_diameter"))
    meas = {k: (g[k] or {}).get("median") for k in GAUGED}
    meas["pitch_diameter_wires"] = g["pitch_diameter_wires"]
    items = []
    for k in wanted + (["pitch_diameter_wires"] if "pitch_diameter" in wanted else []):
        base = "pitch_diameter" if k == "pitch_diameter_wires" else k
        if lim is not None:
            items.append(limit_item(k, *lim[base], meas[k]))
        else:
            items.append(item(k, spec[base], meas[k], spec["tolerance"]))
    details = {f"{k}_range": _r([g[k]["min"], g[k]["max"]]) if g[k] else None for k in GAUGED}
    details.update(wire_diameter=_r(g["wire"]), over_wires=_r(g["over_wires"]), wires=g["wires"])
    if lim is not None:
        details["designation"] = lim["designation"]
    return items, details


def check_thread(spec: dict, result) -> dict:
    zlo, zhi = spec["z"]
    m = M.measure_thread(result.part, zlo, zhi, spec["angles"], inside=spec.get("side") == "inside")
    items = [item("lead", spec["lead"], m["lead"], spec["lead_tolerance"]),
             item("starts", spec["starts"], m["starts"], None, unit=""),
             item("hand", spec["hand"], m["hand"], None, unit="")]
    if spec.get("root_diameter") is not None:
        items.append(item("root_diameter", spec["root_diameter"], m["root_diameter"], spec["tolerance"]))
    details = {"z": [zlo, zhi], "roots": len(m["roots"]), "pitch": _r(m["pitch"]),
               "root_diameter_min": _r(m["root_diameter_min"]), "root_diameter_max": _r(m["root_diameter_max"])}
    gi, gd = _gauge_items(spec, result.part)
    items += gi
    details.update(gd)
    if spec.get("phase") is not None:
        if m["lead"] and m["hand"] and m["roots"]:
            meas = M.thread_phases(m["roots"], m["lead"], m["hand"], spec["phase_z"])
            groups = M.assign_phases(meas, spec["phase"])
            for k, g in enumerate(groups):
                items.append(item(f"phase[{k + 1}]", g["expected"], g["measured"], spec["phase_tolerance"], "deg",
                                  passed=g["error"] is not None and abs(g["error"]) <= spec["phase_tolerance"]
                                  and g["spread"] <= spec["phase_tolerance"]))
            details["phase_spread"] = [_r(g["spread"]) for g in groups]
        else:
            for k, e in enumerate(spec["phase"]):
                items.append(item(f"phase[{k + 1}]", e, None, spec["phase_tolerance"], "deg"))
    return _record(spec, items, details)


def check_ramp(spec: dict, result) -> dict:
    (za, zb), (ra, rb) = spec["z"], spec["radius"]
    z, r = M.root_radius_profile(result.part, za, zb, spec["step"])
    want = ra + (z - za) * (rb - ra) / (zb - za)
    dev = r - want
    if np.all(np.isfinite(dev)):
        k = int(np.argmax(np.abs(dev)))
        worst, at = float(dev[k]), float(z[k])
    else:
        worst, at = None, None
    it = item("root_radius_deviation", 0.0, worst, spec["tolerance"])
    return _record(spec, [it, item("root_radius_start", ra, float(r[0]), spec["tolerance"]),
                          item("root_radius_end", rb, float(r[-1]), spec["tolerance"])],
                   {"worst_z": _r(at), "samples": len(z), "step": spec["step"]})


def _feature_items(spec: dict, found: dict, keys: tuple[str, ...]) -> tuple[list[dict], dict]:
    """Items comparing the median of each measured feature value with ``spec``'s, and the
    range over the sections as details."""
    items, details = [], {}
    for k in keys:
        if spec.get(k) is None:
            continue
        m = found.get(k)
        items.append(item(k, spec[k], None if m is None else m["median"], spec["tolerance"]))
        details[f"{k}_range"] = None if m is None else _r([m["min"], m["max"]])
    return items, details


def check_bore(spec: dict, result) -> dict:
    found = turned.bore(result.part, spec["z"], spec["face"])
    items, details = _feature_items(spec, found, ("diameter", "depth", "tip_depth"))
    return _record(spec, items, {"z": spec["z"], "face": spec["face"], **details})


def check_groove(spec: dict, result) -> dict:
    found = turned.groove(result.part, spec["at"], spec["side"] == "inside", spec["reach"])
    items, details = _feature_items(spec, found, ("diameter", "depth", "width", "center"))
    return _record(spec, items, {"at": spec["at"], "side": spec["side"], **details})


def check_shoulder(spec: dict, result) -> dict:
    lo, hi = spec["range"]
    found = turned.shoulder(result.part, spec["diameter"], lo, hi, spec["side"] == "inside", spec["expected"])
    z = found["z"]
    return _record(spec, [item("z", spec["expected"], None if z is None else z["median"], spec["tolerance"])],
                   {"diameter": spec["diameter"], "range": [lo, hi], "z_range": None if z is None else
                    _r([z["min"], z["max"]])})


def _stock_top(result) -> float:
    return float(result.stock.bounding_box()[5])


def _slot_items(spec: dict, result, directions: tuple[str, ...], widths, centers) -> tuple[list, dict]:
    x, y = spec["at"]
    tol = spec["tolerance"]
    floor = M.depth_at(result.part, x, y)
    items, details = [], {"at": [x, y]}
    if spec.get("floor") is not None:
        items.append(item("floor", spec["floor"], floor, tol))
    if widths is not None or centers is not None:
        zmeas = spec.get("z")
        if zmeas is None:
            zmeas = 0.5 * ((floor if floor is not None else _stock_top(result)) + _stock_top(result))
        details["z"] = _r(zmeas)
        for k, dr in enumerate(directions):
            g = M.gap_at(result.part, (x, y, zmeas), dr)
            w = g[1] - g[0] if g else None
            c = 0.5 * (g[0] + g[1]) if g else None
            details[f"gap_{dr}"] = _r(list(g)) if g else None
            if widths is not None and widths[k] is not None:
                items.append(item(f"width_{dr}" if len(directions) > 1 else "width", widths[k], w, tol))
            if centers is not None and centers[k] is not None:
                items.append(item(f"center_{dr}" if len(directions) > 1 else "center", centers[k], c, tol))
    return items, details


def check_slot(spec: dict, result) -> dict:
    items, details = _slot_items(spec, result, (spec["direction"],),
                                 [spec.get("width")], [spec.get("center")])
    return _record(spec, items, details)


def check_pocket(spec: dict, result) -> dict:
    items, details = _slot_items(spec, result, ("x", "y"), spec.get("size"), spec.get("center"))
    return _record(spec, items, details)


def check_depth(spec: dict, result) -> dict:
    x, y = spec["at"]
    return _record(spec, [item("z", spec["expected"], M.depth_at(result.part, x, y), spec["tolerance"])],
                   {"at": [x, y]})


def check_volume(spec: dict, result) -> dict:
    removed = float(result.stock.volume() - result.part.volume())
    tol = spec["tolerance"] if spec.get("tolerance") is not None else 0.01 * abs(spec["removed"])
    return _record(spec, [item("removed_volume", spec["removed"], removed, tol, "mm^3")])


def check_design(spec: dict, result, design=None) -> dict:
    if design is None:
        design = M.load_solid(spec["path"])
    c = M.compare_design(result.part, design, result.stock)
    items = []
    if spec.get("max_gouge") is not None:
        items.append(item("gouge_volume", 0.0, c["gouge_volume"], spec["max_gouge"], "mm^3",
                          passed=c["gouge_volume"] <= spec["max_gouge"]))
    if spec.get("max_excess") is not None:
        items.append(item("excess_volume", 0.0, c["excess_volume"], spec["max_excess"], "mm^3",
                          passed=c["excess_volume"] <= spec["max_excess"]))
    if spec.get("max_deviation") is not None:
        items.append(item("worst_deviation", 0.0, c["worst_deviation"], spec["max_deviation"],
                          passed=abs(c["worst_deviation"]) <= spec["max_deviation"]))
    return _record(spec, items, {"path": spec["path"], "gouge_volume": _r(c["gouge_volume"]),
                                 "excess_volume": _r(c["excess_volume"]),
                                 "worst_deviation": _r(c["worst_deviation"]),
                                 "worst_location": _r(c["worst_location"])})


EVALUATORS = {"diameter": check_diameter, "thread": check_thread, "ramp": check_ramp, "bore": check_bore,
              "groove": check_groove, "shoulder": check_shoulder, "slot": check_slot,
              "pocket": check_pocket, "depth": check_depth, "volume": check_volume, "design": check_design}


def evaluate(spec: dict, result) -> dict:
    """One check record for ``spec`` on ``result``."""
    return EVALUATORS[spec["kind"]](spec, result)


def format_failures(records: list[dict]) -> str:
    """A readable table of the failed items of ``records`` (for assertion messages and the CLI)."""
    lines = []
    for rec in records:
        if rec["passed"]:
            continue
        lines.append(f"check {rec['name']!r} ({rec['kind']}) failed:")
        for it in rec["items"]:
            mark = "ok  " if it["passed"] else "FAIL"
            tol = "" if it["tolerance"] is None else f" +- {it['tolerance']}"
            lines.append(f"  {mark} {it['quantity']}: expected {it['expected']}{tol} {it['unit']}".rstrip()
                         + f", measured {it['measured']}")
    return "\n".join(lines)
