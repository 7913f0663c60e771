"""The random differential run: programs from tests/support/ngc_gen.py through cutsim's rs274ngc
interpreter and LinuxCNC's rs274, compared move by move (tests/support/rs274.py).

    python bench/ngc_differential.py [--seed S] [--count N] [--keep DIR] [--lathe-share F] [--g70-comp F]

Prints the counts (same, both refuse, documented differences, divergences); each divergence's program
is written to DIR
(default /tmp/ngc-divergences) with the verdict. ``--lathe-share`` (default 0.2) and ``--g70-comp`` (0.3)
are the generator's shares of programs with a lathe cycle and of those whose G70 runs under cutter
radius compensation (1 and 1 focus a run on it). Exit status 1 when any diverged. One rs274 at a time
(one worker): the machine's cores are shared.
"""
from __future__ import annotations

import argparse
import os
import random
import sys
import tempfile
from collections import Counter
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))

from support.ngc_gen import TOOL_TABLE, program  # noqa: E402
from support.rs274 import compare  # noqa: E402


def run(seed: int, count: int, keep: str | None, quiet: bool = False, **options) -> Counter:
    counts: Counter = Counter()
    with tempfile.TemporaryDirectory() as tmp:
        tbl = os.path.join(tmp, "tools.tbl")
        Path(tbl).write_text(TOOL_TABLE)
        for i in range(count):
            text = program(random.Random(seed * 1_000_003 + i), **options)
            path = os.path.join(tmp, f"case{i}.ngc")
            Path(path).write_text(text)
            verdict = compare(path, tbl)
            key = ("same" if verdict == "same" else "both refuse" if verdict.startswith("same")
                   else "documented" if verdict.startswith("documented") else "divergence")
            counts[key] += 1
            if key == "divergence" and keep:
                os.makedirs(keep, exist_ok=True)
                Path(keep, f"seed{seed}-case{i}.ngc").write_text(text)
                Path(keep, f"seed{seed}-case{i}.txt").write_text(verdict + "\n")
                if not quiet:
                    print(f"case {i}: {verdict.splitlines()[0]}", file=sys.stderr)
    return counts


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seed", type=int, default=20261126)
    ap.add_argument("--count", type=int, default=200)
    ap.add_argument("--keep", default="/tmp/ngc-divergences")
    ap.add_argument("--lathe-share", type=float, default=0.2)
    ap.add_argument("--g70-comp", type=float, default=0.3)
    a = ap.parse_args()
    counts = run(a.seed, a.count, a.keep, lathe_share=a.lathe_share, g70_comp=a.g70_comp)
    print(f"seed {a.seed}: {a.count} programs: {counts['same']} same, {counts['both refuse']} both refuse, "
          f"{counts['documented']} documented differences, {counts['divergence']} divergences")
    return 1 if counts["divergence"] else 0


if __name__ == "__main__":
    sys.exit(main())
