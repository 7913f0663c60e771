"""DIR/index.html: one row per job -- thumbnail (only when a job wrote images), the job linked to
its report, status, exit status, removed volume, warnings, time, message -- rendered with jinja2
from ``templates/index.html.j2`` (package data)."""
from __future__ import annotations

import os

from .records import FAILED, PASSED, SIMULATED_EXITS

_COLOURS = {PASSED: "#1a7f37", FAILED: "#b35900"}
_ERROR_COLOUR = "#cf222e"


def _template():
    import jinja2

    env = jinja2.Environment(loader=jinja2.PackageLoader("cutsim.batch", "templates"),
                             autoescape=jinja2.select_autoescape(["html", "j2"]), keep_trailing_newline=True)
    return env.get_template("index.html.j2")


def index_html(summary, timings: dict, out_dir: str) -> bytes:
    """The index of ``summary`` (a BatchSummary) with the jobs' ``timings``; links and thumbnails
    only to files that are in ``out_dir``. A resumed job's time is the stored run's, marked so."""
    rows = []
    for j in summary["jobs"]:
        n = j["name"]
        t = timings.get(n, {})
        simulated = os.path.isfile(os.path.join(out_dir, n, "report.json")) and j["exit"] in SIMULATED_EXITS
        rows.append({"name": n, "status": j["status"], "colour": _COLOURS.get(j["status"], _ERROR_COLOUR),
                     "exit": j["exit"], "removed_volume": j["removed_volume"], "warnings": len(j["warnings"]),
                     "seconds": t.get("seconds", 0.0), "resumed": bool(t.get("resumed")), "message": j["message"],
                     "thumb": bool(j.get("images")) and os.path.isfile(os.path.join(out_dir, n, "iso.png")),
                     "link": ("report.html" if j.get("images") else "report.json") if simulated else None})
    return _template().render(
        total=summary["total"], counts=", ".join(f"{v} {k}" for k, v in summary["counts"].items()),
        scheduler=str(summary.timings.get("scheduler")), wall_seconds=summary.timings.get("wall_seconds", 0),
        resumed=any(t.get("resumed") for t in timings.values()),
        thumbs=any(j.get("images") for j in summary["jobs"]), rows=rows).encode()
