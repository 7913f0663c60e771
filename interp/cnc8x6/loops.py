"""CNC8x6 G73 loops counted without running them: a program whose loops would execute more blocks
than [simulation] max_blocks is refused before it runs, naming the loops responsible."""
from __future__ import annotations

from bisect import bisect_left
from dataclasses import dataclass

from ..core.lexer import Block, fmt_count

# -- G73 loops without running them ----------------------------------------------------------------
# A G73 block at index g jumping to index t <= g with Q repeats: reached with no counter, it arms
# one with Q and jumps back while the counter is above zero; at zero it deletes the counter and
# execution falls through. Since every jump goes backwards, passing block g forwards means loop g
# has completed, so whenever block g is reached first in an activation, every loop with a G73
# between its target and g is disarmed. Hence (by induction over the G73 blocks from the last) every
# program ends, and one activation of loop g executes 1 + Q * (cost(t, g) + 1) blocks, where
#     cost(s, e) = (e - s) + sum of W_h over the G73 blocks h in [s, e),   W_h = Q_h * (cost(t_h, h) + 1)
# is the number of blocks executed from s (no counters armed) until block e is reached. For properly
# nested loops this is the sum over blocks of the product of (Q + 1) over the loops enclosing them;
# overlapping loops (a loop re-armed by an outer one) are counted exactly as well.


@dataclass(frozen=True)
class Jump:
    index: int  # the G73 block
    target: int  # the block it jumps to
    repeats: int | str  # Q (the text as written when it is not known statically)
    line: int
    col: int  # of the G73 word


def static_jumps(blocks: list[Block], labels: dict[int, int]) -> tuple[list[Jump], int]:
    """The G73 jumps with literal, valid L and Q in block order, and ``end``: how many blocks from the
    start the static count covers. It stops after the first program end (M02/M30) and before the
    first G73 whose L or Q is missing, invalid (an error when it runs) or read from a parameter."""
    jumps: list[Jump] = []
    for i, b in enumerate(blocks):
        if any(w.letter == "M" and w.value in (2, 30) for w in b.words):
            return jumps, i + 1  # the program ends here; a G73 in this block does not jump
        g73 = [w for w in b.words if w.letter == "G" and w.value == 73]
        if not g73:
            continue
        lw, qw = b.find("L"), b.find("Q")
        if len(g73) != 1 or len(lw) != 1 or len(qw) != 1:
            return jumps, i
        lw, qw = lw[0], qw[0]
        if lw.param is not None or qw.param is not None or lw.value != int(lw.value) or qw.value != int(qw.value) \
                or qw.value < 0 or int(lw.value) not in labels or labels[int(lw.value)] > i:
            return jumps, i
        jumps.append(Jump(i, labels[int(lw.value)], int(qw.value), b.line, g73[0].col))
    return jumps, len(blocks)


class _Counts:
    """cost(s, e) of the comment above, from prefix sums of W over the jumps in block order."""

    def __init__(self, jumps: list[Jump]):
        self.jumps = jumps
        self.index = [j.index for j in jumps]
        self.prefix = [0]  # prefix[k] = W of jumps[:k]
        self.w: list[int] = []
        for j in jumps:
            w = j.repeats * (self.cost(j.target, j.index) + 1)
            self.w.append(w)
            self.prefix.append(self.prefix[-1] + w)

    def cost(self, s: int, e: int) -> int:
        lo, hi = bisect_left(self.index, s), bisect_left(self.index, e)
        hi = min(hi, len(self.w))
        return (e - s) + self.prefix[hi] - self.prefix[min(lo, hi)]


def count_executions(jumps: list[Jump], end: int) -> int:
    """Blocks executed from the start until ``end`` (see static_jumps) is passed."""
    return _Counts(jumps).cost(0, end)


def crossing_block(jumps: list[Jump], end: int, limit: int) -> tuple[int, list[Jump]]:
    """Where execution number ``limit + 1`` happens (the program must run that far): the block's
    index and the loops whose counters are armed then, outermost first."""
    c = _Counts(jumps)
    s, e, budget = 0, end, limit  # from block s (no counters armed), ``budget`` blocks run before it
    armed: list[Jump] = []
    while True:
        pos = s
        for k in range(bisect_left(c.index, s), bisect_left(c.index, e)):
            j = jumps[k]
            if budget < j.index - pos:  # in the blocks before G73 j
                return pos + budget, armed
            budget -= j.index - pos
            if budget < 1 + c.w[k]:  # within the activation of loop j
                if budget == 0:  # its first execution: not armed yet
                    return j.index, armed
                budget = (budget - 1) % (c.cost(j.target, j.index) + 1)  # into the repeat that passes
                s, e = j.target, j.index
                armed.append(j)
                break
            budget -= 1 + c.w[k]
            pos = j.index + 1
        else:
            return pos + budget, armed


def crossing_loops(jumps: list[Jump], end: int, limit: int) -> list[Jump]:
    """The loops responsible when execution passes ``limit`` blocks, outermost (the last G73) first:
    those armed then and those enclosing the block being executed (they repeat it); empty when none."""
    pos, armed = crossing_block(jumps, end, limit)
    enclosing = [j for j in jumps if j.target <= pos <= j.index]
    return sorted(set(armed) | set(enclosing), key=lambda j: -j.index)


def heaviest_loops(jumps: list[Jump]) -> list[Jump]:
    """The loop adding the most executions, then within its span the loop adding the most, and so
    on (outermost first); empty when no loop repeats anything."""
    c = _Counts(jumps)
    chain: list[Jump] = []
    lo, hi = 0, len(jumps)  # candidates: jumps[lo:hi]
    while lo < hi:
        k = max(range(lo, hi), key=lambda i: (c.w[i], i))
        if c.w[k] == 0:
            break
        chain.append(jumps[k])
        lo, hi = bisect_left(c.index, jumps[k].target), k
    return chain


def _describe(chain: list[Jump]) -> str:
    """'Q20 at line 5 inside Q20 at line 6': innermost first, at most six loops named."""
    parts = [f"Q{j.repeats} at line {j.line}" for j in reversed(chain)]
    if len(parts) > 6:
        parts = parts[:3] + ["..."] + parts[-2:]
    return " inside ".join(parts)


def loops_error(blocks: list[Block], labels: dict[int, int], limit: int) -> tuple[int, int, str] | None:
    """(line, column, message) when the program's G73 loops would execute more than ``limit`` blocks;
    the error points at the outermost G73 running when the count passes the limit (see
    count_executions). None when they do not, or when no loop is to blame."""
    jumps, end = static_jumps(blocks, labels)
    total = count_executions(jumps, end)
    if total <= limit:
        return None
    chain = crossing_loops(jumps, end, limit)
    if not chain:  # passed after the loops: name the one that adds the most blocks
        chain = heaviest_loops(jumps)
    if not chain:  # no loop at all: the runtime guard names the block
        return None
    outer = chain[0]
    return outer.line, outer.col, (f"G73 loops would execute {fmt_count(total)} blocks ({_describe(chain)}), more than "
                                   f"the limit of {limit:,} set by [simulation] max_blocks; treated as a program that "
                                   "does not end")


def running_loops_error(blocks: list[Block], active, limit: int) -> tuple[int, int, str] | None:
    """(line, column, message) for the runtime guard when G73 loops are armed (``active``: their
    block indices, outermost first): loops the static count cannot see (L or Q from a parameter)."""
    if not active:
        return None
    chain = []
    for idx in active:
        g = blocks[idx]
        gw = next(w for w in g.words if w.letter == "G" and w.value == 73)
        q = g.find("Q")
        chain.append(Jump(idx, idx, q[0].raw if q else "?", g.line, gw.col))
    outer = chain[0]
    return outer.line, outer.col, (f"G73 loops ({_describe(chain)}) execute more than the limit of {limit:,} blocks "
                                   "set by [simulation] max_blocks; treated as a program that does not end")
