"""The setup as the rest of cutsim sees it (docs/setup.md)."""
from __future__ import annotations

from dataclasses import dataclass, field

from cutsim.base.specs import MachineSpec, StockSpec, ToolSpec
from cutsim.interp.core.modal import MAX_BLOCKS
from cutsim.stock.build import DEFAULT_MAX_TRIANGLES


@dataclass
class Setup:
    path: str
    machine: MachineSpec
    stock: StockSpec
    tools: list[ToolSpec]
    parameters: dict[int, float] = field(default_factory=dict)
    constants: dict[int, float] = field(default_factory=dict)
    tolerance: float = 0.002
    fail_on_warning: bool = False
    checks: list[dict] = field(default_factory=list)
    max_blocks: int = MAX_BLOCKS
    max_triangles: int = DEFAULT_MAX_TRIANGLES
    stock_where: tuple[int, int] = (0, 0)  # line, column of the key that sizes the stock (errors of build_stock)
    # what only the setup can say about the machine (docs/setup.md; interp.InterpConfig's fields of these names)
    axes: dict[str, str] = field(default_factory=dict)  # [machine] axes: extra axis name -> "rotary" | "linear"
    m_functions: frozenset[int] = frozenset()  # [machine] m_functions
    h_functions: frozenset[int] = frozenset()  # [machine] h_functions
    transformations: frozenset[str] = frozenset()  # [machine] transformations: Cartesian ones ("TRAFO")
    subprogram_path: tuple[str, ...] = ()  # [machine] subprogram_path: absolute folders
    tool_table: str = ""  # [machine] tool_table: a LinuxCNC .tbl (rs274ngc), absolute path or ""
    parameter_file: str = ""  # [machine] parameter_file: a LinuxCNC .var (rs274ngc), absolute path or ""
    external_subprograms: frozenset[str] = frozenset()  # [machine] external_subprograms: upper case, no folder
    thread_acceleration: float = 0.0  # [machine] thread_acceleration (mm/s^2; 0: not given)
    variables: dict[str, float | str] = field(default_factory=dict)  # [variables]: upper-case name -> value
    work_offsets: dict[str, tuple[float, float, float]] = field(default_factory=dict)  # [work_offsets]: "G54" -> xyz
    tool_names: dict[str, int] = field(default_factory=dict)  # [[tool]] name (as written) -> number
