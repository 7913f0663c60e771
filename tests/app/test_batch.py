"""``cutsim batch``: the shipped examples on the local pool and on a Dask LocalCluster give the same
summary and the same bytes; a crash, a hang and an out-of-memory are their job's result; a resumed
batch re-runs nothing that is unchanged; a bad manifest is ``MANIFEST:LINE:COL`` with exit 2.

Expected volumes come from the drawings in the programs' comments: POCKET1 50 x 30, corner radius
8, 8 deep (8 * (1500 - (4 - pi) * 64) mm^3); SLOT1 four slots 30 long (round ends), 12 wide, 6 deep
(24 * ((30 - 12) * 12 + pi * 36)). The tolerance allowed is the chordal tolerance times the length
of the curved walls times the depth: chords lie inside the true arcs.
"""
from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from conftest import REPO_EXAMPLES
from cutsim.batch import batch_command, load_manifest, run_batch

TOL = 0.1  # coarse, to keep the runs short
SIN = REPO_EXAMPLES / "sinumerik"
POCKET1_VOLUME = 8 * (50 * 30 - (4 - math.pi) * 8 ** 2)
POCKET1_TOL = 8 * TOL * 2 * math.pi * 8
SLOT1_VOLUME = 4 * 6 * ((30 - 12) * 12 + math.pi * 6 ** 2)
SLOT1_TOL = 4 * 6 * TOL * 2 * math.pi * 6

MANIFEST = f"""\
# three shipped examples at a coarse tolerance
[defaults]
tolerance = {TOL}
timeout = 300

[[job]]
program = "{SIN / 'pocket1.mpf'}"
expect = {{ removed_volume = {POCKET1_VOLUME!r}, removed_volume_tol = {POCKET1_TOL!r} }}

[[job]]
program = "{SIN / 'slot1.mpf'}"
setup = "{SIN / 'slot1.toml'}"
expect = {{ removed_volume = {SLOT1_VOLUME!r}, removed_volume_tol = {SLOT1_TOL!r} }}

[[job]]
name = "isg-taper"
program = "{REPO_EXAMPLES / 'isg-lathe' / 'taper.nc'}"
# its checks hold the root to 0.02 mm: at a 0.1 mm chordal tolerance they fail (exit 1)
[job.expect]
exit = 1
"""
JOBS = ["isg-taper", "pocket1", "slot1"]


@pytest.fixture(scope="module")
def work(tmp_path_factory):
    d = tmp_path_factory.mktemp("batch")
    (d / "jobs.toml").write_text(MANIFEST)
    return d


@pytest.fixture(scope="module")
def local_run(work):
    """The manifest through the command (the real CLI path: each job is `python3 -m cutsim simulate`)."""
    out = work / "local"
    r = CliRunner().invoke(batch_command, [str(work / "jobs.toml"), "--out", str(out), "--jobs", "2", "-q"])
    return r, out


def _summary(out: Path) -> dict:
    return json.loads((out / "summary.json").read_text())


def test_local_pool_runs_the_examples(local_run):
    r, out = local_run
    assert r.exit_code == 0, r.output
    s = _summary(out)
    assert [j["name"] for j in s["jobs"]] == JOBS
    by = {j["name"]: j for j in s["jobs"]}
    assert all(j["status"] == "passed" for j in s["jobs"]), s
    assert abs(by["pocket1"]["removed_volume"] - POCKET1_VOLUME) <= POCKET1_TOL
    assert abs(by["slot1"]["removed_volume"] - SLOT1_VOLUME) <= SLOT1_TOL
    assert by["isg-taper"]["exit"] == 1 and by["isg-taper"]["checks_failed"]
    for name in JOBS:  # DIR/<job>/ as `cutsim simulate` writes it
        marker = json.loads((out / name / ".cutsim-output.json").read_text())
        assert marker["files"] == ["part.stl", "report.json"]
        rep = json.loads((out / name / "report.json").read_text())
        assert rep["removed_volume"] == by[name]["removed_volume"] and rep["tolerance"] == TOL
    # one JUnit testcase per job; the expected exit 1 is no failure
    suite = ET.parse(out / "junit.xml").getroot().find("testsuite")
    assert [c.get("name") for c in suite.findall("testcase")] == JOBS
    assert suite.get("failures") == "0" and suite.get("errors") == "0"
    html = (out / "index.html").read_text()
    assert all(f">{n}</a>" in html for n in JOBS)
    timings = json.loads((out / "timings.json").read_text())
    assert timings["scheduler"] == "local:2" and set(timings["jobs"]) == set(JOBS)


def test_dask_cluster_gives_the_same_summary_and_bytes(work, local_run):
    distributed = pytest.importorskip("distributed")
    _, local_out = local_run
    out = work / "dask"
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, host="127.0.0.1", dashboard_address=None,
                                  processes=True) as cluster, distributed.Client(cluster) as client:
        summary = run_batch(str(work / "jobs.toml"), str(out), client=client, progress=False)
        workers = len(client.nthreads())
    assert workers == 2
    assert summary.timings["scheduler"].startswith("dask:tcp://127.0.0.1")
    assert (out / "summary.json").read_bytes() == (local_out / "summary.json").read_bytes()
    assert dict(summary) == _summary(local_out)
    for name in JOBS:
        for f in ("part.stl", "report.json", ".cutsim-output.json"):
            assert (out / name / f).read_bytes() == (local_out / name / f).read_bytes(), (name, f)


def test_resume_reruns_nothing_unchanged(work, local_run):
    _, local_out = local_run
    out = work / "resume"
    shutil.copytree(local_out, out)
    before = {n: (out / n / "part.stl").stat().st_mtime_ns for n in JOBS}
    s = run_batch(str(work / "jobs.toml"), str(out), resume=True, progress=False)
    assert all(t["resumed"] for t in s.timings["jobs"].values())
    assert dict(s) == _summary(local_out)
    assert {n: (out / n / "part.stl").stat().st_mtime_ns for n in JOBS} == before
    # a changed option changes the key: that job (only) runs again
    manifest = work / "jobs2.toml"
    manifest.write_text(MANIFEST.replace('name = "isg-taper"', 'name = "isg-taper"\ntolerance = 0.2'))
    s2 = run_batch(str(manifest), str(out), resume=True, progress=False)
    assert {n for n, t in s2.timings["jobs"].items() if not t["resumed"]} == {"isg-taper"}
    assert json.loads((out / "isg-taper" / "report.json").read_text())["tolerance"] == 0.2
    # a deleted result is not a finished result
    (out / "pocket1" / "report.json").unlink()
    s3 = run_batch(str(manifest), str(out), resume=True, progress=False)
    assert {n for n, t in s3.timings["jobs"].items() if not t["resumed"]} == {"pocket1"}
    assert dict(s3) == dict(s2)


FAKE = r'''
import os, sys, time
prog = os.path.basename(sys.argv[2])
if prog.startswith("crash"):
    import ctypes
    ctypes.string_at(0)                      # a real segmentation fault
elif prog.startswith("hang"):
    with open(os.environ["HANG_PID_FILE"], "w") as f:
        f.write(str(os.getpid()))
    time.sleep(600)
elif prog.startswith("oom"):
    hog = []
    while True:                              # until the address-space limit stops it
        hog.append(bytearray(16 << 20))
else:                                        # everything else: the real command
    os.execv(sys.executable, [sys.executable, "-m", "cutsim"] + sys.argv[1:])
'''


def test_crash_hang_and_out_of_memory_are_job_results(tmp_path, monkeypatch):
    fake = tmp_path / "fake.py"
    fake.write_text(FAKE)
    setup = tmp_path / "pocket1.toml"
    shutil.copy(SIN / "pocket1.toml", setup)
    for n in ("crash", "hang", "oom", "pocket1"):
        shutil.copy(SIN / "pocket1.mpf", tmp_path / f"{n}.mpf")
    monkeypatch.setenv("HANG_PID_FILE", str(tmp_path / "hang.pid"))
    jobs = [{"name": n, "program": str(tmp_path / f"{n}.mpf"), "setup": str(setup), "tolerance": TOL}
            for n in ("crash", "hang", "oom", "pocket1")]
    jobs[1]["timeout"] = 3.0
    jobs[2]["memory"] = 400
    s = run_batch(jobs, str(tmp_path / "out"), workers=2, command=[sys.executable, str(fake)], progress=False)
    by = {j["name"]: j for j in s["jobs"]}
    assert by["crash"]["status"] == "crashed" and by["crash"]["signal"] == "SIGSEGV"
    assert by["hang"]["status"] == "timeout"
    pid = int((tmp_path / "hang.pid").read_text())
    with pytest.raises(ProcessLookupError):  # the hanging process was killed, not left behind
        os.kill(pid, 0)
    assert by["oom"]["status"] == "memory", by["oom"]
    # the other job of the batch is unaffected
    assert by["pocket1"]["status"] == "passed"
    assert abs(by["pocket1"]["removed_volume"] - POCKET1_VOLUME) <= POCKET1_TOL
    assert s.exit_status == 1
    assert not (tmp_path / "out" / "crash").exists()
    suite = ET.parse(tmp_path / "out" / "junit.xml").getroot().find("testsuite")
    kinds = {c.get("name"): [(e.tag, e.get("type")) for e in c] for c in suite.findall("testcase")}
    assert kinds == {"crash": [("error", "crashed")], "hang": [("error", "timeout")],
                     "oom": [("error", "memory")], "pocket1": []}
    # resume re-runs the errors, not the finished job
    s2 = run_batch(jobs[:1] + jobs[3:], str(tmp_path / "out"), resume=True, command=[sys.executable, str(fake)],
                   progress=False)
    assert {n: t["resumed"] for n, t in s2.timings["jobs"].items()} == {"crash": False, "pocket1": True}


def _pocket1_design(depth: float):
    """The drawing of pocket1.mpf as a solid: the 100 x 80 x 20 block minus a 50 x 30 pocket with
    corner radius 8, turned 20 degrees about its centre (50, 40), ``depth`` deep."""
    import trimesh
    from manifold3d import CrossSection, JoinType, Manifold

    block = Manifold.cube([100, 80, 20]).translate([0, 0, -20])
    outline = CrossSection.square([34, 14], center=True).offset(8, JoinType.Round, circular_segments=512)
    pocket = Manifold.extrude(outline, depth + 1).translate([0, 0, -depth]).rotate([0, 0, 20]).translate([50, 40, 0])
    m = (block - pocket).to_mesh()
    return trimesh.Trimesh(np.asarray(m.vert_properties)[:, :3], np.asarray(m.tri_verts))


def test_regression_mode_reports_changed_solids(tmp_path):
    _pocket1_design(8).export(tmp_path / "right.stl")
    _pocket1_design(7).export(tmp_path / "wrong.stl")
    jobs = [{"name": n, "program": str(SIN / "pocket1.mpf"), "setup": str(SIN / "pocket1.toml"), "tolerance": TOL,
             "expect": {"reference": str(tmp_path / f"{n}.stl"), "reference_tol": POCKET1_TOL}}
            for n in ("right", "wrong")]
    s = run_batch(jobs, str(tmp_path / "out"), workers=2, progress=False)
    by = {j["name"]: j for j in s["jobs"]}
    assert s["changed"] == ["wrong"]
    assert by["right"]["status"] == "passed" and by["wrong"]["status"] == "failed"
    # the chords leave material inside the drawn corners: at most the chordal band
    assert 0 <= by["right"]["regression"]["symmetric_difference"] <= POCKET1_TOL
    # one more millimetre of pocket floor, 50 x 30 with R8 corners
    floor = 50 * 30 - (4 - math.pi) * 64
    assert abs(by["wrong"]["regression"]["symmetric_difference"] - floor) <= POCKET1_TOL
    # the same part against an earlier batch's parts (--reference-dir): unchanged
    ref_dir = tmp_path / "out"
    plain = {k: v for k, v in jobs[0].items() if k != "expect"}
    import cutsim  # the public spelling: cutsim.batch.run_batch(jobs, out, client=None, **options)

    s2 = cutsim.batch.run_batch([plain], str(tmp_path / "again"), reference_dir=str(ref_dir), progress=False)
    assert s2["jobs"][0]["regression"]["symmetric_difference"] == 0.0 and s2["changed"] == []


def test_folder_and_csv_manifests(tmp_path):
    jobs = load_manifest(str(REPO_EXAMPLES))
    pairs = sorted(p for p in REPO_EXAMPLES.rglob("*") if p.suffix in (".nc", ".mpf") and p.with_suffix(".toml").is_file())
    assert len(jobs) == len(pairs) and "sinumerik-pocket1" in {j.name for j in jobs}
    assert all(Path(j.setup) == Path(j.program).with_suffix(".toml") for j in jobs)
    (tmp_path / "jobs.csv").write_text(
        "name,program,setup,tolerance,expect_exit,expect_removed_volume,expect_removed_volume_tol\n"
        f"p1,{SIN / 'pocket1.mpf'},,0.05,0,11560.5,40\n"
        f"s1,{SIN / 'slot1.mpf'},{SIN / 'slot1.toml'},,,,\n")
    p1, s1 = load_manifest(str(tmp_path / "jobs.csv"))
    assert (p1.name, p1.tolerance, p1.expect) == ("p1", 0.05, {"exit": 0, "removed_volume": 11560.5,
                                                                "removed_volume_tol": 40.0})
    assert p1.setup == str(SIN / "pocket1.toml") and s1.tolerance is None and s1.expect == {}


@pytest.mark.parametrize("text, where, words", [
    ('[[job]]\nprogram = "a.nc"\n\n[[job]]\nprogram = "b.nc"\ntimeout = -1\n', "6:1", "timeout"),
    ('[defaults]\ntolerance = 0.1\n\n[[job]]\nprogram = "a.nc"\ncolour = "red"\n', "6:1", "colour: unknown key"),
    ('[[job]]\nprogram = "a.nc"\n[[job]]\nprogram = "b/a.nc"\n', "3:1", "used twice"),
    ('[[job]]\nprogram = "a.nc"\nexpect = { exit = 3 }\n', "3:12", "exit"),
    ('[[job]]\nprogram = "a.nc\n', "2:16", "Illegal character"),
    ('[defaults]\ntolerance = 0.1\n', "1:1", "no [[job]]"),
    ('[[job]]\nprogram = "a.nc"\ntimeout = ' + "9" * 5000 + "\n", "3:11", "too many digits"),  # tomllib's ValueError
])
def test_bad_manifest_is_an_error_at_its_line(tmp_path, text, where, words):
    m = tmp_path / "m.toml"
    m.write_text(text)
    r = CliRunner().invoke(batch_command, [str(m), "--out", str(tmp_path / "out")])
    assert r.exit_code == 2, r.output
    assert r.output.startswith(f"{m}:{where}: error: ") and words in r.output, r.output
    assert r.output.count("\n") == 1 and not (tmp_path / "out").exists()


def test_bad_csv_manifest(tmp_path):
    m = tmp_path / "m.csv"
    m.write_text("program,tolerance\na.nc,0.1\nb.nc,fine\n")
    r = CliRunner().invoke(batch_command, [str(m), "--out", str(tmp_path / "out")])
    assert r.exit_code == 2 and r.output == f"{m}:3:6: error: tolerance: 'fine' is not a number\n", r.output


def test_batch_is_a_cutsim_command():
    """`cutsim batch` is reachable from the main command line (not only as batch_command)."""
    proc = subprocess.run([sys.executable, "-m", "cutsim", "batch", "--help"], capture_output=True, text=True)
    assert proc.returncode == 0 and "MANIFEST" in proc.stdout, proc.stderr


def test_a_subprogram_on_the_setup_search_path_is_part_of_the_job_key(tmp_path):
    """A job's key covers the subprogram files it calls from [machine] subprogram_path, so editing one
    makes the stored result stale; a file of the same name beside the program is the one used."""
    from cutsim.batch import referenced_files

    (tmp_path / "subs").mkdir()
    (tmp_path / "subs" / "HOLE.spf").write_text("PROC HOLE\nG1 Z-1 F100\nM17\n")
    (tmp_path / "subs" / "OTHER.spf").write_text("PROC OTHER\nM17\n")
    prog = tmp_path / "main.mpf"
    prog.write_text("G0 X0 Y0 Z5\nHOLE\nM30\n")
    setup = tmp_path / "s.toml"
    setup.write_text('[machine]\nkind = "mill"\ndialect = "sinumerik"\nsubprogram_path = ["subs"]\n')
    assert referenced_files(str(prog), str(setup)) == [str(tmp_path / "subs" / "HOLE.spf")]
    (tmp_path / "HOLE.spf").write_text("PROC HOLE\nM17\n")
    assert referenced_files(str(prog), str(setup)) == [str(tmp_path / "HOLE.spf")]


def test_resume_keeps_the_stored_runs_times(work, local_run):
    """A resumed job was not run again: junit.xml, timings.json and index.html give the time of the
    run that made its result (not 0), and the index says so."""
    _, local_out = local_run
    out = work / "resume-times"
    shutil.copytree(local_out, out)
    stored = json.loads((local_out / "timings.json").read_text())["jobs"]
    s = run_batch(str(work / "jobs.toml"), str(out), resume=True, progress=False)
    assert {n: (t["seconds"], t["host"], t["resumed"]) for n, t in s.timings["jobs"].items()} == {
        n: (t["seconds"], t["host"], True) for n, t in stored.items()}
    assert all(t["seconds"] > 0 for t in stored.values())
    suite = ET.parse(out / "junit.xml").getroot().find("testsuite")
    assert {c.get("name"): c.get("time") for c in suite.findall("testcase")} == {
        n: f"{t['seconds']:.3f}" for n, t in stored.items()}
    html = (out / "index.html").read_text()
    assert "0.0 (resumed)" not in html and html.count(" (stored run)</td>") == len(JOBS)
    assert "is that of the run that made their result" in html
    for n, t in stored.items():
        assert f'<td class="n">{t["seconds"]:.1f} (stored run)</td>' in html


class _Cells(__import__("html.parser").parser.HTMLParser):
    """The cells of every table row: [[(tag, text), ...], ...]."""

    def __init__(self):
        super().__init__()
        self.rows, self.cell = [], None

    def handle_starttag(self, tag, attrs):
        if tag == "tr":
            self.rows.append([])
        elif tag in ("td", "th"):
            self.cell = [tag, ""]
            self.rows[-1].append(self.cell)
        elif tag == "img" and self.cell is not None:
            self.cell[1] += "<img>"

    def handle_data(self, data):
        if self.cell is not None:
            self.cell[1] += data

    def handle_endtag(self, tag):
        if tag in ("td", "th"):
            self.cell = None


def _table(html: str) -> list[list[tuple[str, str]]]:
    p = _Cells()
    p.feed(html)
    return [[tuple(c) for c in row] for row in p.rows]


def test_index_without_images_has_no_thumbnail_column(local_run):
    _, out = local_run
    rows = _table((out / "index.html").read_text())
    assert [t for _, t in rows[0]] == ["job", "status", "exit", "removed mm³", "warnings", "time s", "message"]
    assert [row[0][1] for row in rows[1:]] == JOBS and all(len(r) == 7 for r in rows)


def test_index_with_images_has_thumbnails(tmp_path):
    """A job that wrote images gets its thumbnail, linked to its report.html; one that did not (its
    own images = false) an empty cell in the column."""
    from cutsim.batch import BatchSummary, index_html

    (tmp_path / "a").mkdir()
    for f in ("iso.png", "report.json", "report.html"):
        (tmp_path / "a" / f).write_bytes(b"x")
    (tmp_path / "b").mkdir()
    (tmp_path / "b" / "report.json").write_bytes(b"{}")
    job = {"status": "passed", "exit": 0, "removed_volume": 1.0, "warnings": [], "message": ""}
    summary = BatchSummary({"jobs": [dict(job, name="a", images=True), dict(job, name="b", images=False)],
                            "counts": {"passed": 2}, "total": 2})
    summary.timings = {"scheduler": "local:1", "wall_seconds": 1.0}
    rows = _table(index_html(summary, {"a": {"seconds": 1.0}, "b": {"seconds": 2.0}}, str(tmp_path)).decode())
    assert [t for _, t in rows[0]][:2] == ["", "job"] and all(len(r) == 8 for r in rows)
    assert [r[0][1] for r in rows[1:]] == ["<img>", ""]
    assert [r[1][1] for r in rows[1:]] == ["a", "b"]
    html = index_html(summary, {"a": {"seconds": 1.0}, "b": {"seconds": 2.0}}, str(tmp_path)).decode()
    assert '<a href="a/report.html"><img src="a/iso.png"' in html and 'href="b/report.json"' in html


def test_closing_summary_on_stdout_progress_on_stderr(work, local_run):
    _, local_out = local_run
    out = work / "resume-streams"
    shutil.copytree(local_out, out)
    r = CliRunner().invoke(batch_command, [str(work / "jobs.toml"), "--out", str(out), "--resume"])
    assert r.exit_code == 0, r.output
    assert r.stdout.startswith("cutsim batch: 3 jobs, 3 passed in ") and r.stdout.count("\n") == 1
    assert r.stderr == "cutsim batch: 3 of 3 jobs resumed\n"
