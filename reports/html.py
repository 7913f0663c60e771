"""report.html: the check table and the images in one self-contained file (images embedded as
base64 data URIs, no scripts, no network)."""
from __future__ import annotations

import base64
import html

from .report import called_from


def _fmt(v) -> str:
    if v is None:
        return "&mdash;"
    if isinstance(v, float):
        return f"{v:.6g}"
    return html.escape(str(v))


def report_html(report: dict, images: dict[str, bytes] | None = None) -> bytes:
    """The HTML report for ``report`` (the report.json dict) with ``images`` ({name: PNG bytes})."""
    e = html.escape
    checks = report.get("checks", [])
    passed = all(c["passed"] for c in checks)
    verdict = "no checks" if not checks else ("all checks passed" if passed else "CHECKS FAILED")
    out = ["<!DOCTYPE html>", '<html lang="en"><head><meta charset="utf-8">',
           f"<title>cutsim: {e(report.get('program', ''))}</title>",
           "<style>body{font-family:sans-serif;margin:2em}table{border-collapse:collapse}"
           "td,th{border:1px solid #999;padding:3px 8px;text-align:left}.pass{background:#d8f0d8}"
           ".fail{background:#f6d0d0}img{max-width:100%;border:1px solid #ccc}</style></head><body>",
           f"<h1>{e(report.get('program', ''))}: {verdict}</h1>",
           "<p>" + ", ".join(f"{k.replace('_', ' ')} {_fmt(report.get(k))}" for k in
                             ("dialect", "blocks", "moves", "stock_volume", "part_volume", "removed_volume",
                              "cycle_time_s", "tolerance")) + "</p>",
           "<h2>Checks</h2>"]
    if checks:
        out.append("<table><tr><th>check</th><th>kind</th><th>quantity</th><th>expected</th><th>measured</th>"
                   "<th>tolerance</th><th>unit</th><th>result</th></tr>")
        for c in checks:
            for it in c["items"] or [{"quantity": "", "expected": None, "measured": None, "tolerance": None,
                                      "unit": "", "passed": False}]:
                cls = "pass" if it["passed"] else "fail"
                out.append(f'<tr class="{cls}"><td>{e(c["name"])}</td><td>{e(c["kind"])}</td>'
                           f'<td>{e(it["quantity"])}</td><td>{_fmt(it["expected"])}</td><td>{_fmt(it["measured"])}</td>'
                           f'<td>{_fmt(it["tolerance"])}</td><td>{e(it["unit"])}</td>'
                           f'<td>{"pass" if it["passed"] else "FAIL"}</td></tr>')
        out.append("</table>")
    else:
        out.append("<p>The setup has no [[check]] tables.</p>")
    warnings = report.get("warnings", [])
    out.append(f"<h2>Warnings ({len(warnings)})</h2><ul>")
    out += [f"<li>{e(w['program'])}:{w['line']}:{w['column']}: {e(w['message'] + called_from(w))}</li>" for w in warnings]
    out.append("</ul>")
    if images:
        out.append("<h2>Images</h2>")
        for name in sorted(images):
            data = base64.b64encode(images[name]).decode("ascii")
            out.append(f'<figure><img alt="{e(name)}" title="{e(name)}" src="data:image/png;base64,{data}">'
                       f"<figcaption>{e(name)}</figcaption></figure>")
    out.append("</body></html>\n")
    return "\n".join(out).encode("utf-8")
