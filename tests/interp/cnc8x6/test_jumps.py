"""CNC8x6 G73 jump loops: the number of executed blocks known before running, the limit
([simulation] max_blocks) refused at once at the outermost G73, and the runtime guard for loops
whose L or Q come from parameters.

The reference counts here come from two independent derivations: for properly nested loops the
sum over blocks of the product of (Q + 1) over the loops enclosing them; for any structure a
literal replay of the jump rule (a counter armed with Q when the G73 is reached without one,
decremented on each jump back, deleted when it reaches zero).
"""
from __future__ import annotations

import math
import random

import pytest

import cutsim
from cutsim import CutsimError
from cutsim.interp import InterpConfig, interpret
from cutsim.interp.cnc8x6 import count_executions, crossing_block, parse, static_jumps


def program(n: int, loops: dict[int, tuple[int, int]], end: bool = False) -> str:
    """n blocks N1..Nn (block i moves to X=i); loops: block index -> (target index, Q)."""
    lines = []
    for i in range(n):
        line = f"N{i + 1} G01 X{i} F100"
        if i in loops:
            t, q = loops[i]
            line += f" G73 L{t + 1} Q{q}"
        lines.append(line)
    if end:
        lines.append(f"N{n + 1} M30")
    return "\n".join(lines) + "\n"


def replay(n: int, loops: dict[int, tuple[int, int]]) -> list[tuple[int, list[int]]]:
    """The jump rule executed literally: (block index, armed G73s in arming order) per execution."""
    out, armed, pc = [], {}, 0
    while pc < n:
        out.append((pc, list(armed)))
        if pc in loops:
            t, q = loops[pc]
            armed.setdefault(pc, q)
            if armed[pc] > 0:
                armed[pc] -= 1
                pc = t
                continue
            del armed[pc]
        pc += 1
    return out


def static(text: str):
    blocks = parse("t.nc", text)
    labels = {int(b.label[1:]): i for i, b in enumerate(blocks)}
    return static_jumps(blocks, labels)


def run(text: str, max_blocks: int = 5_000_000, **kw):
    cfg = InterpConfig(dialect="cnc8x6", machine_kind="mill", start=(0.0, 0.0, 0.0), max_blocks=max_blocks, **kw)
    return interpret("t.nc", text, cfg)


def fails(text: str, max_blocks: int, **kw) -> CutsimError:
    with pytest.raises(CutsimError) as e:
        run(text, max_blocks, **kw)
    return e.value


def random_nested(rng: random.Random, n: int) -> dict[int, tuple[int, int]]:
    """Loops whose intervals [target, G73] are disjoint or contain one another."""
    loops: dict[int, tuple[int, int]] = {}
    for g in range(n):
        if rng.random() < 0.5:
            t = rng.randint(0, g)
            if all(not t2 < t <= g2 for g2, (t2, _) in loops.items()):  # each earlier loop: before t or inside
                loops[g] = (t, rng.randint(0, 4))
    return loops


def test_nested_count_is_the_product_formula():
    rng = random.Random(7)
    for _ in range(300):
        n = rng.randint(1, 10)
        loops = random_nested(rng, n)
        product_sum = sum(math.prod(q + 1 for g, (t, q) in loops.items() if t <= i <= g) for i in range(n))
        jumps, end = static(program(n, loops))
        assert count_executions(jumps, end) == product_sum
        assert len(replay(n, loops)) == product_sum
        if product_sum < 5000:
            assert run(program(n, loops)).blocks == product_sum


def test_any_structure_ends_and_is_counted_exactly():
    # Overlapping loops re-arm each other, yet every program ends (each G73 passed forwards is
    # disarmed): the count and the block where any limit is passed agree with the literal replay.
    rng = random.Random(11)
    for _ in range(400):
        n = rng.randint(1, 8)
        loops = {g: (rng.randint(0, g), rng.randint(0, 3)) for g in range(n) if rng.random() < 0.45}
        trace = replay(n, loops)
        jumps, end = static(program(n, loops))
        assert count_executions(jumps, end) == len(trace)
        if len(trace) < 5000:
            assert run(program(n, loops)).blocks == len(trace)
        for limit in range(0, len(trace), max(1, len(trace) // 40)):
            pos, armed = crossing_block(jumps, end, limit)
            assert (pos, [j.index for j in armed]) == trace[limit]


def test_limit_is_exact_and_refused_before_running():
    # N10 and N20 run Q+1 = 4 times inside N30's loop, N30 itself 4 times, N40 once: 13 blocks
    text = "N10 G01 X1 F100\nN20 X2\nN30 G73 L10 Q3\nN40 X0\n"
    assert run(text, max_blocks=13).blocks == 13
    e = fails(text, 12)  # passed at N40, after the loop: the loop is still what adds the blocks
    assert (e.line, e.col) == (3, 5)
    assert "G73 loops would execute 13 blocks (Q3 at line 3), more than the limit of 12" in e.message
    e = fails(text, 11)  # passed inside the loop
    assert (e.line, e.col) == (3, 5) and "would execute 13 blocks" in e.message


def test_program_end_inside_the_structure_stops_the_count():
    # M30 in the second block: the loop after it never runs, whatever its Q
    text = "N10 G01 X1 F100\nN20 M30\nN30 G73 L10 Q99999999\n"
    assert run(text, max_blocks=10).blocks == 2


def test_nested_error_names_the_outermost_loop():
    # inner loop N20..N30 Q99, outer N10..N40 Q99: 100*(1 + 100*2 + 1) + 1 blocks
    text = "N10 G01 X1 F100\nN20 X2\nN30 G73 L20 Q99\nN40 G73 L10 Q99\nN50 X0\n"
    total = 100 * (1 + 100 * 2 + 1) + 1
    e = fails(text, 1000)
    assert (e.line, e.col) == (4, 5)
    assert f"would execute {total:,} blocks (Q99 at line 3 inside Q99 at line 4)" in e.message
    e = fails(text, total - 1)  # passed at N50, after the loops: the same two are named
    assert (e.line, e.col) == (4, 5) and "(Q99 at line 3 inside Q99 at line 4)" in e.message


def test_endless_example_fails_at_once():
    # tests/data/programs/mill/helix-endless.nc: N20 and N30 run Q + 1 times, N10 and N40 once
    q = 99999999
    text = "N10 Z1.05 G10\nN20 G09 G02 X0 Y0 I10 F100\nN30 G73 L20 Q99999999\nN40 G98\n"
    e = fails(text, 5_000_000)
    assert (e.line, e.col) == (3, 5) and f"{2 * (q + 1) + 2:,} blocks" in e.message


def test_parameter_loops_fall_back_to_the_runtime_guard():
    # Q from a parameter is only known when the block runs: the guard names the active G73s
    text = "R10=100\nN10 G01 X1 F100\nN15 G73 L10 QR10\nN20 G73 L10 Q100\n"
    e = fails(text, 1000)
    assert (e.line, e.col) == (4, 5)
    assert "G73 loops (QR10 at line 3 inside Q100 at line 4) execute more than the limit of 1,000 blocks" in e.message
    total = 1 + (100 + 1) * (2 * (100 + 1) + 1)  # R10=, then 101 x (N10 and N15 101 times each, N20)
    assert run(text, total).blocks == total


def test_setup_max_blocks(tmp_path):
    setup = tmp_path / "s.toml"
    setup.write_text('[machine]\nkind = "mill"\ndialect = "cnc8x6"\nstart = [0, 0, 50]\n'
                     '[stock]\nshape = "box"\nx = [0, 10]\ny = [0, 10]\nz = [0, 10]\n'
                     '[[tool]]\nkind = "endmill"\ndiameter = 2.0\n'
                     '[simulation]\ntolerance = 0.1\nmax_blocks = 20\n')
    assert cutsim.load_setup(str(setup)).max_blocks == 20
    prog = tmp_path / "p.nc"
    prog.write_text("N10 G00 X20 Y20 Z60\nN20 X30\nN30 G73 L10 Q9\n")  # 30 blocks, all clear of the stock
    with pytest.raises(CutsimError) as e:
        cutsim.simulate(str(prog), str(setup))
    assert (e.value.line, e.value.col) == (3, 5) and "more than the limit of 20" in e.value.message
    setup.write_text(setup.read_text().replace("max_blocks = 20", "max_blocks = 30"))
    assert cutsim.simulate(str(prog), str(setup)).report["blocks"] == 30
