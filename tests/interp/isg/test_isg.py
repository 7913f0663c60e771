"""The Beckhoff TwinCAT (ISG) dialect: program structure, G33 with I/J/K leads, S.OFFSET, errors,
and the thread solids of seed 004's programs measured against conventions.md.

Groove phase (conventions.md): with M03 and a cut towards -Z starting at z0 with start offset a,
a groove at the workpiece angle phi lies at z = z0 + L*(phi + a)/360 (mod L). Roots: the half-plane
section of a screw sweep holds the tool point where the tool passes phi, so each root is at the
programmed radius X/2, up to the chordal tolerance deeper (chords of the helix lie inside it) and
never shallower. Measurements use manifold's double-precision mesh (float32 vertices round z near
100 mm to about 4 um, more than the accuracy asserted here).
"""
from __future__ import annotations

import os
import subprocess
import sys
import unicodedata
from pathlib import Path

import numpy as np
import pytest
import trimesh

import cutsim
from conftest import EXAMPLES
from cutsim.interp import CutsimError, InterpConfig, interpret, transcript
from cutsim.interp import canon
from support.geometry import section, wrap

HERE = Path(__file__).resolve().parents[2]  # tests/
ISG = EXAMPLES / "isg-lathe"
OWN = HERE / "data" / "programs" / "isg"
PHIS = (0.0, 90.0, 200.0, 321.7)


# -- helpers ---------------------------------------------------------------------------------------
def run(text: str, diameter: bool = False, start=(150.0, 0.0, 200.0), dialect: str = "isg") -> canon.Program:
    cfg = InterpConfig(dialect=dialect, machine_kind="lathe", diameter_programming=diameter, start=start)
    return interpret("t.nc", text, cfg)


def fails(text: str, **kw) -> CutsimError:
    with pytest.raises(CutsimError) as e:
        run(text, **kw)
    return e.value


def records(prog, kind):
    return [r for r in prog.records if isinstance(r, kind)]


def mesh64(result) -> trimesh.Trimesh:
    m = result.part.to_mesh64()
    return trimesh.Trimesh(np.asarray(m.vert_properties)[:, :3], np.asarray(m.tri_verts), process=False)


def roots(mesh, phi, zlo, zhi, rmin, below, w):
    """(z, r) of the groove roots in the half-plane at ``phi``: section vertices above ``rmin`` that
    are the lowest within +-``w`` along z (the flanks of a V groove fall monotonically to its root),
    deeper than ``below`` and with z in [zlo, zhi]."""
    pts = section(mesh, phi).reshape(-1, 2)
    pts = np.unique(np.round(pts[pts[:, 0] > rmin], 9), axis=0)
    pts = pts[np.argsort(pts[:, 1])]
    z, r = pts[:, 1], pts[:, 0]
    lo, hi = np.searchsorted(z, z - w), np.searchsorted(z, z + w, side="right")
    out = []
    for i in range(len(z)):
        if zlo <= z[i] <= zhi and r[i] < below and r[i] <= r[lo[i]:hi[i]].min() and (not out or z[i] - out[-1][0] > w):
            out.append((z[i], r[i]))
    return np.array(out).reshape(-1, 2)


M70 = """%L Laengsgewinde
N100 G33 Z48 K1.5
N110 G00 X72
N120 Z105
N130 M29
%G33 (Gewindetiefe 0.92 mm)
N10 G51
N15 T1 D1 M03 S400
N20 G00 X72 Z105
"""


# -- program structure -----------------------------------------------------------------------------
def test_golden_transcript_m70():
    prog = ISG / "m70x1.5.nc"
    proc = subprocess.run([sys.executable, "-m", "cutsim", "moves", str(prog), "--setup", str(prog.with_suffix(".toml"))],
                          capture_output=True, text=True, encoding="utf-8")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout == (HERE / "data" / "golden" / "isg" / "isg_m70x1.5.txt").read_text(encoding="utf-8")


def test_m70_subprogram_passes_carry_their_call_sites():
    text = (ISG / "m70x1.5.nc").read_text(encoding="utf-8")
    prog = run(text, start=(150.0, 0.0, 200.0))
    syncs = records(prog, canon.SyncedFeed)
    # five calls (N30 repeated) at lines 12..20, each cutting from Z105 to Z48 at the fed-in depth
    assert [s.src.calls for s in syncs] == [(("t.nc", n),) for n in (12, 14, 16, 18, 20)]
    assert {s.src.line for s in syncs} == {2} and {s.src.label for s in syncs} == {"N100"}
    assert [s.start[0] for s in syncs] == [69.54, 69.08, 68.62, 68.16, 68.16]
    assert all(s.start[2] == 105 and s.end[2] == 48 and s.lead == 1.5 and s.lead_axis == "Z"
               and s.start_angle == 0 and s.diameter for s in syncs)
    assert prog.blocks == 15 + 5 * 4  # main blocks plus four body blocks per call
    assert isinstance(prog.records[-1], canon.ProgramEnd) and prog.final_position == (150.0, 0.0, 200.0)
    assert prog.warnings == []


def test_rest_of_calling_block_runs_first_and_m17_returns():
    prog = run("%L Längsgewinde\nG00 X80\nM17\n%MAIN\nN10 G01 X60 Z10 F100 LL Längsgewinde\nN20 G01 X50\nM30\n")
    kinds = [type(r).__name__ for r in prog.moves]
    assert kinds == ["Feed", "Rapid", "Feed"]
    assert [m.end[0] for m in prog.moves] == [60, 80, 50]
    assert prog.moves[1].src.calls == (("t.nc", 5),)


def test_non_ascii_names_match_in_any_unicode_form():
    nfd = unicodedata.normalize("NFD", "Längsgewinde")
    prog = run(f"%L Längsgewinde\nG00 X80\nM29\n%MAIN\nLL {nfd}\nM30\n")
    assert [m.end[0] for m in prog.moves] == [80]


def test_nested_calls_list_every_call_site():
    prog = run("%L A\nG01 X10 F1\nLL B\nM29\n%L B\nG01 X20\nM29\n%M\nLL A\nM30\n")
    assert [m.src.calls for m in prog.moves] == [(("t.nc", 9),), (("t.nc", 9), ("t.nc", 3))]
    assert [m.src.line for m in prog.moves] == [2, 6]


def test_comments_titles_and_repeated_labels():
    prog = run("; header comment\n%P1 (a title; not a comment)  ; a comment\n"
               "N10 G01 X10 F100 (inline) ; c\nN10 G01 X20\n\n   ; only a comment\nN10 M30\n")
    assert [m.end[0] for m in prog.moves] == [10, 20] and prog.blocks == 3


# -- G33 -------------------------------------------------------------------------------------------
def test_g33_modal_until_g01_and_lead_modal_until_end():
    prog = run("%P\nG51 M03 S100\nG00 X40 Z10\nG33 Z0 K2\nZ-10\nG01 X50 F100\nZ-20\nG00 Z10\nG33 Z0\nM30\n")
    syncs = records(prog, canon.SyncedFeed)
    assert [(s.src.line, s.lead, s.lead_axis) for s in syncs] == [(4, 2, "Z"), (5, 2, "Z"), (9, 2, "Z")]
    feeds = records(prog, canon.Feed)
    assert [f.src.line for f in feeds] == [6, 7]


def test_lead_address_names_the_axis():
    for addr, axis in (("I", "X"), ("J", "Y"), ("K", "Z")):
        prog = run(f"%P\nG51 M03 S10\nG00 X100 Z105\nG33 Z90 X1 {addr}5.0\nM30\n")
        (s,) = records(prog, canon.SyncedFeed)
        assert (s.lead, s.lead_axis) == (5.0, axis)


def test_seed_taper_leads_along_x():
    text = (ISG / "taper.nc").read_text(encoding="utf-8")
    (s,) = records(run(text), canon.SyncedFeed)
    assert (s.start, s.end, s.lead, s.lead_axis, s.diameter) == ((100, 0, 105), (1, 0, 90), 5.0, "X", True)
    assert s.src.calls == (("t.nc", 15),)


def test_s_offset_forms_modal_and_equal_to_cnc8x6_i():
    prog = run("%P\nG51 M03 S10\nG00 X72 Z105\nG33 Z48 K1.5\nG00 X72\nZ105\nG33 Z48 S.OFFSET=180\n"
               "G00 X72\nS.OFFSET 45.5\nZ105\nG01 X70 F100\nG33 Z48\ns.offset=0\nG33 Z40\nM30\n")
    assert [s.start_angle for s in records(prog, canon.SyncedFeed)] == [0, 180, 45.5, 0]
    isg = records(run("%P\nG51 M03 S10\nG00 X72 Z105\nG33 Z48 K1.5 S.OFFSET=180\nM30\n"), canon.SyncedFeed)[0]
    cnc = records(run("G00 X72 Z105 M03 S10\nG33 Z48 F1.5 I180\nM30\n", diameter=True, dialect="cnc8x6"),
                  canon.SyncedFeed)[0]
    assert (isg.start, isg.end, isg.lead, isg.start_angle, isg.diameter) == (
        cnc.start, cnc.end, cnc.lead, cnc.start_angle, cnc.diameter)


def test_g51_g52_switch_diameter_and_radius_values():
    prog = run("%P\nG01 X30 Z0 F100\nG51\nG01 X80\nG52 G01 X50\nM30\n", start=(50.0, 0.0, 10.0))
    ends = [(m.end[0], m.diameter) for m in prog.moves]
    assert ends == [(30, False), (80, True), (50, False)]
    assert prog.moves[1].start == (60.0, 0.0, 0.0)  # radius 30 is diameter 60


# -- errors ----------------------------------------------------------------------------------------
def test_seed_spelling_fails_through_the_cli(tmp_path):
    out = tmp_path / "out"
    prog = OWN / "seed-spelling.nc"
    proc = subprocess.run([sys.executable, "-m", "cutsim", "simulate", str(prog), "--setup",
                           str(ISG / "m70x1.5.toml"), "--out", str(out), "-q"],
                          capture_output=True, text=True, encoding="utf-8",
                          env={**os.environ, "PYTHONIOENCODING": "utf-8"})
    assert proc.returncode == 2
    assert f"{prog}:12:8: error: unknown subprogram 'Längsgewinde'; did you mean 'Laengsgewinde'?" in proc.stderr
    assert "Traceback" not in proc.stderr
    assert not out.exists()


@pytest.mark.parametrize("text, line, col, words", [
    # unknown subprogram: a case difference gets a suggestion, an unrelated name the list
    (M70 + "LL laengsgewinde\nM30\n", 10, 4, ["unknown subprogram 'laengsgewinde'", "did you mean 'Laengsgewinde'"]),
    (M70 + "G01 X70 F9 LL Gewinde\nM30\n", 10, 15, ["unknown subprogram 'Gewinde'", "Laengsgewinde"]),
    # recursion, direct and through another subprogram (reported at the call that closes the loop)
    ("%L A\nG01 X1 F1\nLL A\nM29\n%M\nLL A\nM30\n", 3, 4, ["recursive", "A -> A"]),
    ("%L A\nLL B\nM29\n%L B\nN5 LL A\nM29\n%M\nLL A\nM30\n", 5, 7, ["recursive", "A -> B -> A", "called from line 2"]),
    # a local subprogram without M29, followed by another program or by the end of the file
    ("%L A\nG01 X1 F1\n%M\nLL A\nM30\n", 1, 4, ["'A' is not ended", "M29", "before line 3"]),
    ("%M\nLL A\nM30\n%L A\nG01 X1 F1\n", 4, 4, ["'A' is not ended", "end of the file"]),
    # G33 with no lead ever programmed (F is no lead), lead zero, signed lead, two leads
    ("%P\nM03 S1\nG01 X10 F100\nG33 Z10\nM30\n", 4, 1, ["G33 without a lead", "I, J or K"]),
    ("%P\nM03 S1\nG33 Z10 K0\nM30\n", 3, 9, ["K0", "must not be zero"]),
    ("%P\nM03 S1\nG33 Z10 K2\nG33 Z0 K0.0\nM30\n", 4, 8, ["K0.0", "must not be zero"]),
    ("%P\nM03 S1\nG33 Z10 K-1.5\nM30\n", 3, 9, ["without a sign"]),
    ("%P\nM03 S1\nG33 Z10 X4 I1 K1.5\nM30\n", 3, 15, ["two leads"]),
    ("%P\nM03 S1\nG33 Z10 K1.5 F200\nM30\n", 3, 14, ["F has no meaning while G33"]),
    # start offsets outside the spindle's modulo range, two in one block
    ("%P\nM03 S1\nG33 Z10 K1.5 S.OFFSET=500\nM30\n", 3, 14, ["S.OFFSET=500", "0 <= offset < 360"]),
    ("%P\nS.OFFSET=-10\nM30\n", 2, 1, ["outside the spindle's modulo range"]),
    ("%P\nS.OFFSET=360\nM30\n", 2, 1, ["outside the spindle's modulo range"]),
    ("%P\nM03 S1\nG33 Z10 K1.5 S.OFFSET=0 S.OFFSET=180\nM30\n", 3, 25, ["two spindle offsets"]),
    ("%P\nS.SPEED=3\nM30\n", 2, 3, ["unknown spindle attribute S.SPEED"]),
    # structure
    ("%L A\nM29\nG01 X1 F1\n%M\nM30\n", 3, 1, ["after the end (M29)"]),
    ("G01 X1 F1\n%M\nM30\n", 1, 1, ["before the first program header"]),
    ("%L A\nM29\n%L A\nM29\n%M\nM30\n", 3, 4, ["defined twice", "line 1"]),
    ("%P\nL Sub\nM30\n", 2, 3, ["global subprogram 'Sub'", "subprogram_path", "LL name"]),
    ("%P\nG01 X1 Q5\nM30\n", 2, 8, ["address 'Q'"]),
    ("%P\nG07 X1\nM30\n", 2, 1, ["unknown G code G07"]),
    ("%P\nG01 X1 K3 F10\nM30\n", 2, 8, ["address K has no meaning"]),
])
def test_errors_have_line_and_column(text, line, col, words):
    e = fails(text)
    assert (e.line, e.col) == (line, col), str(e)
    for w in words:
        assert w in e.message, str(e)


def test_errors_inside_a_subprogram_name_the_call():
    e = fails("%L A\nG33 Z10 K0\nM29\n%M\nM03 S1\nN40 LL A\nM30\n")
    assert (e.line, e.col) == (2, 9) and "called from line 6" in e.message


# -- thread solids ---------------------------------------------------------------------------------
def test_m70_root_diameter_and_groove_phase():
    """Seed 004's M70x1.5 (four cuts and a spring cut through LL) on the bar z 88..100: root
    diameter 68.16 and grooves at z = 105 + 1.5*phi/360 (mod 1.5) over the whole cut length.
    Tolerance 0.001 so that the root *diameter* (twice the chordal error) stays within 2 um."""
    tol = 0.001
    r = cutsim.simulate(str(ISG / "m70x1.5.nc"), str(OWN / "short.toml"), tolerance=tol)
    assert r.report["warnings"] == []
    mesh = mesh64(r)
    for phi in PHIS:
        rt = roots(mesh, phi, 88.3, 99.7, 33.0, 34.5, 0.3)
        assert 7 <= len(rt) <= 8, (phi, rt)  # 11.4 mm of thread, one groove per 1.5 mm
        diam_err = 2 * rt[:, 1] - 68.16
        assert np.all(diam_err <= 4e-6) and np.all(diam_err >= -0.002), (phi, diam_err)
        assert np.all(np.abs(wrap(rt[:, 0] - (105 + 1.5 * phi / 360), 1.5)) < 0.002), phi
        assert np.allclose(np.diff(rt[:, 0]), 1.5, atol=0.002)


def test_two_start_grooves_half_a_lead_apart():
    """Seed 004's two-start program: the S.OFFSET=180 start lies where conventions.md puts it,
    z = 105 + 1.5*(phi + 180)/360, i.e. 0.75 from the first start's grooves."""
    tol = 0.002
    r = cutsim.simulate(str(ISG / "two-start.nc"), str(OWN / "short.toml"), tolerance=tol)
    mesh = mesh64(r)
    for phi in PHIS:
        rt = roots(mesh, phi, 88.3, 99.7, 33.0, 34.5, 0.3)
        assert np.all(np.abs(rt[:, 1] - 34.08) <= tol + 2e-6), phi
        assert np.allclose(np.diff(rt[:, 0]), 0.75, atol=0.002), (phi, np.diff(rt[:, 0]))
        first = np.abs(wrap(rt[:, 0] - (105 + 1.5 * phi / 360), 1.5)) < 0.002
        second = np.abs(wrap(rt[:, 0] - (105 + 1.5 * (phi + 180) / 360), 1.5)) < 0.002
        assert np.all(first ^ second) and first.sum() >= 7 and second.sum() >= 7, (phi, rt)


def test_three_starts_equally_spaced():
    """tests/data/programs/isg/three-start.nc: lead K3 with S.OFFSET 0/120/240 gives three grooves per lead, 1 mm
    apart, each start at z = 15 + 3*(phi + a)/360 (mod 3)."""
    tol = 0.002
    r = cutsim.simulate(str(OWN / "three-start.nc"), str(OWN / "three-start.toml"), tolerance=tol)
    mesh = mesh64(r)
    for phi in PHIS:
        rt = roots(mesh, phi, 0.4, 11.6, 13.0, 14.8, 0.3)
        assert np.all(np.abs(rt[:, 1] - 14.4) <= tol + 2e-6), phi
        assert np.allclose(np.diff(rt[:, 0]), 1.0, atol=0.002), (phi, np.diff(rt[:, 0]))
        hits = [np.abs(wrap(rt[:, 0] - (15 + 3 * (phi + a) / 360), 3.0)) < 0.002 for a in (0, 120, 240)]
        assert np.all(sum(h.astype(int) for h in hits) == 1), (phi, rt)
        assert all(h.sum() >= 3 for h in hits), phi


def test_offset_turns_the_groove_against_the_spindle():
    """An asymmetric offset (90) tells the sense apart, which 180 and 0/120/240 cannot: the groove
    lies at z = 15 + 3*(phi + 90)/360 (mod 3), a quarter lead towards +Z from offset 0."""
    tol = 0.002
    r = cutsim.simulate(str(OWN / "offset90.nc"), str(OWN / "three-start.toml"), tolerance=tol)
    mesh = mesh64(r)
    for phi in PHIS:
        rt = roots(mesh, phi, 0.4, 11.6, 13.0, 14.8, 0.3)
        assert len(rt) >= 3 and np.all(np.abs(rt[:, 1] - 14.4) <= tol + 2e-6), phi
        assert np.all(np.abs(wrap(rt[:, 0] - (15 + 3 * (phi + 90) / 360), 3.0)) < 0.002), (phi, rt)
