"""The machine model the kinematics needs (from the setup's [machine] table)."""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class MachineSpec:
    kind: str = "lathe"  # "lathe" | "mill"
    dialect: str = "cnc8x6"
    diameter_programming: bool = True
    m03: str = "positive"  # sense of M03 about +Z: "positive" | "negative"
    start: tuple[float, float, float] | None = None  # program values; None = clear of the stock
    rapid: float = 10000.0  # mm/min, for the cycle time
    feed: float = 100.0  # mm/min assumed when a program feeds without F (cycle time only)
