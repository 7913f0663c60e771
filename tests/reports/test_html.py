"""report.html: what a reader needs at a glance (verdict, units, setup, checks linked to their setup
line, warnings without absolute machine paths, versions), self-contained, and clean in a real
browser (headless Chromium: no console errors, every image decodes, a non-blank page)."""
import base64
import io
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import cutsim
from cutsim.reports.html import report_html
from conftest import external_tool

HERE = Path(__file__).resolve().parents[1] / "data" / "programs" / "checks"


def _png(w=8, h=6, color=(200, 30, 30)):
    from PIL import Image

    buf = io.BytesIO()
    Image.new("RGB", (w, h), color).save(buf, format="PNG")
    return buf.getvalue()


def _report(setup, program_path, checks=None, warnings=None):
    return {"program": "multipass.nc", "dialect": "cnc8x6",
            "machine": {"kind": "lathe", "diameter_programming": True, "m03": "ccw"}, "tolerance": 0.01,
            "blocks": 12, "moves": 30, "stock_volume": 16000.5, "part_volume": 15900.25, "removed_volume": 100.25,
            "cycle_time_s": 1.657, "final_position": [30.0, 0.0, 5.0], "last_cut_position": None,
            "triangles": 1234, "warnings": warnings or [], "checks": checks or []}


def _check(name, line, passed, measured=26.18):
    return {"name": name, "kind": "thread", "line": line, "passed": passed, "details": {},
            "items": [{"quantity": "root_diameter", "expected": 26.177, "measured": measured, "tolerance": 0.03,
                       "unit": "mm", "passed": passed},
                      {"quantity": "hand", "expected": "right", "measured": "right", "tolerance": None, "unit": "",
                       "passed": True}]}


def test_summary_setup_checks_warnings(tmp_path, monkeypatch):
    setup = cutsim.load_setup(str(HERE / "multipass.toml"))
    setup_lines = (HERE / "multipass.toml").read_text().splitlines()
    line = next(i for i, s in enumerate(setup_lines, 1) if s.strip() == "[[check]]")
    monkeypatch.chdir(HERE.parent)  # the run's directory: tests/
    prog = str(HERE / "multipass.nc")  # absolute, as a user may give it
    w = {"line": 7, "column": 3, "program": prog, "message": "feed F0 ignored"}
    html = report_html(_report(setup, prog, [_check("M27 thread", line, False, 26.25)], [w]),
                       {"b.png": _png(), "a.png": _png(color=(0, 0, 200))}, captions={"b.png": "the B view"},
                       setup=setup, order=["b.png", "a.png"]).decode("utf-8")
    # verdict and units
    assert "FAIL: 1 of 1 check(s) failed (M27 thread)" in html
    assert re.search(r"<td>cycle time</td><td[^>]*>1\.657 \(0:01\.7 min:s\)</td><td>s</td>", html)
    assert re.search(r"<td>removed volume</td><td[^>]*>100\.25</td><td>mm\u00b3</td>", html)  # tolerance 0.01
    assert re.search(r"<td>chordal tolerance</td><td[^>]*>0\.01</td><td>mm</td>", html)
    # setup: stock, tools, tolerance; the setup file's lines with anchors, the check links to its line
    assert "revolved profile (r, z) mm: (0, 0), (13.5, 0), (13.5, \u22128)" in html
    assert re.search(r"<td>T9</td><td>thread</td><td>included angle 60\u00b0, nose radius 0 mm; holder shank "
                     r"20 \u00d7 20 mm</td>", html)
    assert f'<a href="#setup-L{line}">multipass.toml:{line}</a>' in html
    assert f'<span id="setup-L{line}"><span class="ln">{line}</span>[[check]]</span>' in html
    assert html.count('<span id="setup-L') == len(setup_lines)
    # measured - expected with a true minus sign, and the failed row marked
    assert "<td class=\"num\">0.073</td>" in html and "FAIL</td>" in html
    # warnings: the program relative to the run's directory, never the machine's absolute path
    assert "checks/multipass.nc:7:3: warning: feed F0 ignored" in html
    assert str(HERE) not in html and os.path.abspath("/") + "work" not in html
    # images in the given order with captions, inlined; versions
    imgs = re.findall(r'<img alt="([^"]+)"[^>]*width="(\d+)" height="(\d+)" src="data:image/png;base64,([^"]+)"',
                      html)
    assert [(n, w_, h_) for n, w_, h_, _ in imgs] == [("b.png", "8", "6"), ("a.png", "8", "6")]
    assert base64.b64decode(imgs[0][3]) == _png()
    assert "<b>b.png</b>: the B view" in html
    import manifold3d  # noqa: F401
    from importlib import metadata

    assert f"cutsim {cutsim.__version__}" in html and f"manifold3d {metadata.version('manifold3d')}" in html
    assert "<script" not in html and "http://" not in html and "https://" not in html


def test_passed_and_deterministic():
    setup = cutsim.load_setup(str(HERE / "multipass.toml"))
    rep = _report(setup, "multipass.nc", [_check("M27 thread", 26, True)])
    a = report_html(rep, {"x.png": _png()}, setup=setup)
    assert a == report_html(rep, {"x.png": _png()}, setup=setup)  # same input, same bytes
    assert "PASS: all 1 check(s) passed" in a.decode()
    none = report_html(_report(setup, "multipass.nc")).decode()
    assert "no checks in the setup" in none and "<h2 id=\"images\">" not in none


def test_html_escapes():
    rep = _report(None, "x", [_check("<b>&", 3, True)])
    html = report_html(rep).decode()
    assert "&lt;b&gt;&amp;" in html and "<b>&" not in html


# ---------------------------------------------------------------------------------------------
def _chromium():
    return external_tool("chromium", "chromium-browser", "google-chrome", "chrome", package="chromium")


def _headless(args, timeout=120):
    exe = _chromium()
    base = [exe, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run", "--disable-extensions",
            "--hide-scrollbars", "--allow-file-access-from-files", f"--user-data-dir={args[0]}"]
    return subprocess.run(base + args[1:], capture_output=True, text=True, timeout=timeout)


CHECKER = """<script>
window.addEventListener('load', function () {
  var out = [];
  document.querySelectorAll('img').forEach(function (im) {
    out.push(im.alt + ' ' + (im.complete ? 1 : 0) + ' ' + im.naturalWidth + 'x' + im.naturalHeight);
  });
  var p = document.createElement('pre'); p.id = 'cutsim-check'; p.textContent = out.join('\\n');
  document.body.appendChild(p);
});
</script>"""


@pytest.mark.browser
def test_report_in_chromium(tmp_path):
    pytest.importorskip("pyvista")
    _chromium()
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "cutsim", "simulate", str(HERE / "multipass.nc"), "--setup",
                           str(HERE / "multipass.toml"), "--out", str(out), "--images", "-q"],
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    page = out / "report.html"
    # 1. the page as shipped: a screenshot, and no console message of level error or warning
    shot = tmp_path / "shot.png"
    r = _headless([str(tmp_path / "profile1"), "--enable-logging=stderr", "--v=0", "--window-size=1200,3000",
                   f"--screenshot={shot}", page.as_uri()])
    assert shot.exists(), r.stderr[-2000:]
    console = [ln for ln in r.stderr.splitlines() if "CONSOLE" in ln or "Uncaught" in ln
               or "Failed to load resource" in ln or "Not allowed to load" in ln]
    assert console == [], console
    from PIL import Image

    img = np.asarray(Image.open(shot).convert("RGB"), dtype=float)
    assert np.mean(np.any(img < 240, axis=2)) > 0.05 and img.std() > 10  # not blank
    # 2. the same markup plus a checker script: every image decoded at its full size
    probe = tmp_path / "probe.html"
    probe.write_text(page.read_text().replace("</body>", CHECKER + "</body>"))
    r = _headless([str(tmp_path / "profile2"), "--dump-dom", "--virtual-time-budget=5000", probe.as_uri()])
    m = re.search(r'<pre id="cutsim-check">(.*?)</pre>', r.stdout, re.S)
    assert m, r.stderr[-2000:]
    rows = m.group(1).strip().splitlines()
    names = sorted(p.name for p in out.glob("*.png"))
    assert sorted(row.split()[0] for row in rows) == names
    for row in rows:
        name, complete, size = row.split()
        with Image.open(out / name) as im:
            assert complete == "1" and size == "%dx%d" % im.size, row


TOOLS_READER = """<script>
window.addEventListener('load', function () {
  var out = [];
  document.querySelectorAll('table').forEach(function (tb) {
    var head = tb.querySelector('tr');
    if (!head || head.innerText.indexOf('geometry') < 0) return;
    tb.querySelectorAll('tr').forEach(function (tr, i) {
      if (i > 0) out.push(Array.from(tr.cells).map(function (c) { return c.innerText; }).join(' | '));
    });
  });
  var p = document.createElement('pre'); p.id = 'cutsim-tools'; p.textContent = out.join('\\n');
  document.body.appendChild(p);
});
</script>"""


@pytest.mark.browser
def test_axial_tools_read_in_chromium(tmp_path):
    """The drilled-and-tapped example's report.html in headless Chromium, its tools table read as
    the page shows it (each cell's rendered text): the centre drill with its pilot, point and
    countersink angles, the twist drill with its diameter and point angle, the tap by its ISO
    designation M10x1.5 with its thread length and chamfer (3 pitches by default: 4.5 mm), all
    as drill-tap-m10.toml gives them (the centre drill's body 2.5 x 5, its pilot 1.2 x 5 long,
    its length 6 x 12.5)."""
    _chromium()
    ex = Path(__file__).resolve().parents[2] / "examples" / "cnc8x6-lathe" / "drill-tap-m10"
    res = cutsim.simulate(str(ex.with_suffix(".nc")), str(ex.with_suffix(".toml")))
    page = tmp_path / "report.html"
    page.write_bytes(report_html(res.report, setup=res.setup))
    probe = tmp_path / "probe.html"
    probe.write_text(page.read_text(encoding="utf-8").replace("</body>", TOOLS_READER + "</body>"), encoding="utf-8")
    r = _headless([str(tmp_path / "profile"), "--dump-dom", "--virtual-time-budget=5000", probe.as_uri()])
    m = re.search(r'<pre id="cutsim-tools">(.*?)</pre>', r.stdout, re.S)
    assert m, r.stderr[-2000:]
    rows = m.group(1).strip().splitlines()
    assert rows == [
        "T1 | centredrill | centre drill, pilot \u00d85 mm (point angle 118\u00b0, 6 mm to the countersink), "
        "countersink 90\u00b0 to \u00d812.5 mm, length 75 mm",
        "T2 | drill | twist drill \u00d88.5 mm, point angle 118\u00b0, flute length 60 mm",
        "T3 | tap | tap M10\u00d71.5 (\u00d810 mm, pitch 1.5 mm), thread length 25 mm, chamfered lead 4.5 mm",
    ], rows


def test_lathe_tools_name_their_holders():
    """An outside insert's row names its holder's shank (the default: 25 for a 12.7 mm insert)."""
    ex = Path(__file__).resolve().parents[2] / "examples" / "cnc8x6-lathe" / "shaft-m30x2.toml"
    setup = cutsim.load_setup(str(ex))
    html = report_html(_report(setup, "shaft-m30x2.nc"), setup=setup).decode()
    assert ("<td>T1</td><td>turning</td><td>ISO insert C 12.7 mm, nose radius 0.8 mm, approach 93\u00b0, hand R; "
            "holder shank 25 \u00d7 25 mm</td>") in html


# ---------------------------------------------------------------------------------------------
# numbers: one documented format (docs/checks.md "Numbers in report.html")
# ---------------------------------------------------------------------------------------------
def _item(quantity, expected, measured, tol, passed=None, unit="mm"):
    if passed is None:
        passed = abs(measured - expected) <= tol
    return {"quantity": quantity, "expected": expected, "measured": measured, "tolerance": tol, "unit": unit,
            "passed": passed}


def _cells(html, quantity):
    m = re.search(rf"<td>{re.escape(quantity)}</td>" + r'<td class="num">([^<]*)</td>' * 4, html)
    assert m, quantity
    return m.groups()


def test_check_numbers_to_the_tolerance_decimals():
    """Expected, measured and difference share one format per row: one decimal finer than the
    tolerance is written with, more when the expected value is written with more; never
    exponent notation, a true minus sign, no signed zero."""
    items = [_item("root_diameter", 13.546, 13.539765, 0.02), _item("lead", 2.0, 1.999967, 0.005),
             _item("depth", -6.0, -6.006297, 0.05), _item("phase", 0.0, -3.3e-05, 2.0, unit="deg"),
             _item("width", 40.0, 33.5397, 0.1, passed=False), _item("floor", -3.0, -3.0000004, 0.01)]
    rep = _report(None, "x", [{"name": "c", "kind": "thread", "line": 3, "passed": False, "details": {},
                               "items": items}])
    html = report_html(rep).decode()
    assert _cells(html, "root_diameter") == ("13.546", "13.540", "\u22120.006", "\u00b10.02")
    assert _cells(html, "lead") == ("2.0000", "2.0000", "0.0000", "\u00b10.005")  # -3.3e-05 rounds to 0
    assert _cells(html, "depth") == ("\u22126.000", "\u22126.006", "\u22120.006", "\u00b10.05")
    assert _cells(html, "phase") == ("0.0", "0.0", "0.0", "\u00b12")
    assert _cells(html, "width") == ("40.00", "33.54", "\u22126.46", "\u00b10.1")
    assert _cells(html, "floor") == ("\u22123.000", "\u22123.000", "0.000", "\u00b10.01")
    table = html[html.index('<table class="checks">'):html.index("</table>", html.index('<table class="checks">'))]
    assert not re.search(r"\d[eE][\u2212+-]?\d", table) and "-" not in re.sub(r"<[^>]*>", "", table)


@pytest.mark.parametrize("seed", range(3))
def test_difference_never_reads_against_the_verdict(seed):
    """Random items near their tolerance (passed = |difference| <= tolerance, the difference a
    whole number of micrometres at least 1 um from the tolerance): the difference shown is beyond
    the tolerance exactly when the item failed."""
    rng = np.random.default_rng(seed)
    items = []
    for k in range(200):
        tol = float(rng.choice([0.5, 0.1, 0.05, 0.02, 0.01, 0.005, 0.002, 0.001]))
        off = int(rng.integers(1, 40)) * float(rng.choice([-1, 1]))
        diff = round(float(rng.choice([-1, 1])) * (round(tol * 1e6) + off) * 1e-6, 6)
        e = round(float(rng.uniform(-50, 50)), int(rng.integers(0, 4)))
        items.append(_item(f"q{k}", e, e + diff, tol, passed=abs(diff) <= tol))
    rep = _report(None, "x", [{"name": "c", "kind": "diameter", "line": 3, "passed": False, "details": {},
                               "items": items}])
    html = report_html(rep).decode()
    for it in items:
        shown = float(_cells(html, it["quantity"])[2].replace("\u2212", "-"))
        assert (abs(shown) > it["tolerance"]) == (not it["passed"]), (it, shown)


@pytest.mark.parametrize("machine,label", [
    ({"kind": "lathe", "diameter_programming": True, "m03": "ccw"}, "final position X (diameter) Y Z"),
    ({"kind": "lathe", "diameter_programming": False, "m03": "ccw"}, "final position X (radius) Y Z"),
    ({"kind": "mill", "diameter_programming": False, "m03": "cw"}, "final position X Y Z"),
])
def test_final_position_says_what_x_is(machine, label):
    rep = dict(_report(None, "x"), machine=machine, final_position=[30.0, 0.0, -5.25], tolerance=0.005)
    html = report_html(rep).decode()
    assert re.search(rf"<td>{re.escape(label)}</td><td[^>]*>30\.000\u20030\.000\u2003\u22125\.250</td><td>mm</td>",
                     html)
