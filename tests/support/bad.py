"""Bad-program folders (tests/data/bad/isg, tests/data/bad/rs274ngc): each program's first line says where it
must stop (``; EXPECT LINE:COL fragment``); the CLI must exit 2 there, write nothing and show no
traceback."""
from __future__ import annotations

import re
from pathlib import Path

from click.testing import CliRunner

from cutsim.cli import main


def expectation(path: Path) -> tuple[int, int, str]:
    m = re.match(r"; EXPECT (\d+):(\d+) (.+)", path.read_text(encoding="utf-8").splitlines()[0])
    assert m, f"{path.name}: first line must be '; EXPECT LINE:COL text'"
    return int(m.group(1)), int(m.group(2)), m.group(3).strip()


def assert_stops_at_its_line(program: Path, setup: Path, tmp_path: Path) -> None:
    line, col, text = expectation(program)
    out = tmp_path / "out"
    res = CliRunner().invoke(main, ["simulate", str(program), "--setup", str(setup), "--out", str(out), "-q"])
    assert res.exit_code == 2, res.output
    msg = res.stderr.strip() if hasattr(res, "stderr") else res.output.strip()
    assert msg.startswith(f"{program}:{line}:{col}: error: "), msg
    assert text in msg, msg
    assert "Traceback" not in res.output
    assert not out.exists() or not any(out.iterdir())
