"""DIR/junit.xml: one ``<testcase>`` per job, failures and errors by status, warnings in
``<system-out>`` (GitLab, Jenkins and GitHub test reporters read it)."""
from __future__ import annotations

from xml.sax.saxutils import escape as _xml_escape

from .records import ERROR_STATUSES, FAILED


def _attr(s) -> str:
    return _xml_escape(str(s), {'"': "&quot;"})


def junit_xml(summary, timings) -> bytes:
    jobs = summary["jobs"]
    failures = sum(j["status"] == FAILED for j in jobs)
    errors = sum(j["status"] in ERROR_STATUSES for j in jobs)
    total = sum(t.get("seconds", 0.0) for t in timings.values())
    out = ['<?xml version="1.0" encoding="UTF-8"?>',
           f'<testsuites name="cutsim batch" tests="{len(jobs)}" failures="{failures}" errors="{errors}" '
           f'time="{total:.3f}">',
           f'  <testsuite name="cutsim batch" tests="{len(jobs)}" failures="{failures}" errors="{errors}" '
           f'skipped="0" time="{total:.3f}">']
    for j in jobs:
        t = timings.get(j["name"], {}).get("seconds", 0.0)
        head = f'    <testcase classname="cutsim.batch" name="{_attr(j["name"])}" file="{_attr(j["program"])}" time="{t:.3f}"'
        body = []
        if j["status"] == FAILED:
            text = "\n".join(j["problems"] + [f"check failed: {c}" for c in j["checks_failed"]])
            body.append(f'      <failure message="{_attr(j["message"])}" type="expectation">{_xml_escape(text)}</failure>')
        elif j["status"] in ERROR_STATUSES:
            body.append(f'      <error message="{_attr(j["message"] or j["status"])}" type="{_attr(j["status"])}">'
                        f'{_xml_escape(j["message"])}</error>')
        if j["warnings"]:
            body.append(f'      <system-out>{_xml_escape(chr(10).join("warning: " + w for w in j["warnings"]))}</system-out>')
        out.append(head + (">" if body else "/>"))
        if body:
            out += body + ["    </testcase>"]
    out += ["  </testsuite>", "</testsuites>", ""]
    return "\n".join(out).encode()
