"""Compare cutsim's rs274ngc interpretation of a program with LinuxCNC's ``rs274`` move by move.

    python bench/vs_rs274.py PROGRAM [--tool-table T.tbl] [--parameters P.var] [--lathe]

Prints "same", a documented difference, or the first divergence with both lines (the normalisations are
listed in tests/support/rs274.py). Exit status 0 when the same or a documented difference, 1 on a
divergence, 2 without rs274.
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from support.rs274 import compare, rs274_path  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("program")
    ap.add_argument("--tool-table", default=None)
    ap.add_argument("--parameters", default=None)
    ap.add_argument("--lathe", action="store_true", help="interpret as on a lathe (the default is a mill)")
    a = ap.parse_args()
    if rs274_path() is None:
        print("rs274 not found (apt-get install linuxcnc-uspace)", file=sys.stderr)
        return 2
    verdict = compare(a.program, a.tool_table, a.parameters, "lathe" if a.lathe else "mill")
    print(verdict)
    return 0 if verdict.startswith(("same", "documented")) else 1


if __name__ == "__main__":
    sys.exit(main())
