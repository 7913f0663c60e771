"""--images: PNGs of the set size that are not blank, and a report.html that embeds every image and
lists every check."""
import base64
import io
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

HERE = Path(__file__).parent / "checks"
pytest.importorskip("pyvista")
from PIL import Image  # noqa: E402

from cutsim.reports.images import HEIGHT, WIDTH  # noqa: E402


def _run(nc, toml, out):
    proc = subprocess.run([sys.executable, "-m", "cutsim", "simulate", str(HERE / nc), "--setup", str(HERE / toml),
                           "--out", str(out), "--images", "-q"], capture_output=True, text=True)
    return proc


def _check_png(path):
    img = np.asarray(Image.open(path).convert("RGB"), dtype=float)
    assert img.shape == (HEIGHT, WIDTH, 3)
    nonwhite = np.mean(np.any(img < 245, axis=2))
    assert 0.05 < nonwhite < 0.95, f"{path.name}: {nonwhite:.3f} of the pixels are drawn"
    assert img.std() > 10
    return img


@pytest.mark.parametrize("nc,toml,names", [
    ("multipass.nc", "multipass.toml", {"iso.png", "section.png"}),
    ("slot.nc", "slot.checks.toml", {"iso.png", "top.png", "deviation.png"}),
])
def test_images_and_html(tmp_path, nc, toml, names):
    out = tmp_path / "out"
    proc = _run(nc, toml, out)
    assert proc.returncode == 0, proc.stderr
    pngs = {p.name for p in out.glob("*.png")}
    assert pngs == names
    for name in names:
        _check_png(out / name)
    html = (out / "report.html").read_text()
    assert "http://" not in html.replace("http://schemas", "") and "https://" not in html and "<script" not in html
    embedded = re.findall(r'<img alt="([^"]+)"[^>]*src="data:image/png;base64,([^"]+)"', html)
    assert {n for n, _ in embedded} == names
    for name, data in embedded:
        assert base64.b64decode(data) == (out / name).read_bytes()
    import json

    for c in json.loads((out / "report.json").read_text())["checks"]:
        assert f"<td>{c['name']}</td>" in html


def test_deviation_map_shows_gouge(tmp_path):
    out = tmp_path / "deep"
    proc = _run("slot-deep.nc", "slot.checks.toml", out)
    assert proc.returncode == 1  # the design check fails on the gouge
    img = _check_png(out / "deviation.png")
    assert "FAIL" in (out / "report.html").read_text()
    del img
