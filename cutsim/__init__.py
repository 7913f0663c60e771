"""cutsim: CNC cutting-process simulator with exact material removal.

Public API::

    result = cutsim.simulate("part.nc", "setup.toml")
    result.part          # manifold3d.Manifold, workpiece frame, mm
    result.mesh()        # trimesh.Trimesh of the part
    result.report        # the report.json dict

Errors in the program or the setup raise :class:`CutsimError` (``FILE:LINE:COL: error: TEXT``).
"""
from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Callable

from cutsim.interp import InterpConfig, interpret
from cutsim.interp.canon import Program
from cutsim.interp.core.files import Unreadable, read_bounded
from cutsim.interp.errors import CutsimError
from cutsim.setup import Setup, load_setup

__version__ = "0.1.0"


def __getattr__(name):  # the pytest helpers, loaded on first use (cutsim.testing)
    if name in ("assert_thread", "assert_matches_design", "assert_checks_pass"):
        import cutsim.testing

        return getattr(cutsim.testing, name)
    if name == "batch":  # the batch runner, imported on first use: cutsim.batch.run_batch(jobs, out, ...)
        import cutsim.batch

        return cutsim.batch
    raise AttributeError(f"module 'cutsim' has no attribute {name!r}")
__all__ = ["CutsimError", "Result", "batch", "Setup", "load_setup", "read_program", "simulate", "__version__",
           "assert_thread", "assert_matches_design", "assert_checks_pass"]


@dataclass
class Result:
    setup: Setup
    program: Program
    plan: object
    stock: object  # manifold3d.Manifold before cutting
    part: object  # manifold3d.Manifold after cutting
    report: dict = field(default_factory=dict)

    def mesh(self):
        """The part as a trimesh.Trimesh (workpiece frame, ``units = "mm"``): the mesh that
        ``cutsim simulate`` writes, closed by position (cutsim.reports.mesh.closed_mesh). It is
        computed once per Result; each call returns a fresh Trimesh of it."""
        import trimesh

        from cutsim.reports.report import mesh_arrays

        cached = self.__dict__.get("_closed_mesh")
        if cached is None or cached[0] is not self.part:
            cached = (self.part, mesh_arrays(self.part))
            self.__dict__["_closed_mesh"] = cached
        v, f = cached[1]
        mesh = trimesh.Trimesh(vertices=v.copy(), faces=f.copy(), process=False)
        mesh.units = "mm"
        return mesh

    @property
    def warnings(self) -> list[dict]:
        return self.report.get("warnings", [])

    @property
    def checks(self) -> list[dict]:
        """The check records (report.json "checks")."""
        return self.report.get("checks", [])

    @property
    def passed(self) -> bool:
        """True when every check passed (and vacuously without checks)."""
        return all(c["passed"] for c in self.checks)

    # measuring functions on the part (cutsim.reports.measure; mm and degrees, workpiece frame)
    def diameters_at(self, z: float, angles: int = 72):
        """Lathe: diameters at height z across angles // 2 directions (numpy array)."""
        from cutsim.reports.measure import diameters_at

        return diameters_at(self.part, z, angles)

    def root_radius_at(self, z: float) -> float:
        """Lathe: smallest radius of the outer boundary at height z (a groove's root)."""
        from cutsim.reports.measure import min_radius_at

        return min_radius_at(self.part, z)

    def thread(self, zlo: float, zhi: float, angles: int = 36) -> dict:
        """Lathe: lead, hand, starts, pitch, root diameter and roots of the thread in [zlo, zhi]."""
        from cutsim.reports.measure import measure_thread

        return measure_thread(self.part, zlo, zhi, angles)

    def depth_at(self, x: float, y: float):
        """Mill: z of the first surface met going down at (x, y) (None if none)."""
        from cutsim.reports.measure import depth_at

        return depth_at(self.part, x, y)

    def gap_at(self, point, direction: str):
        """Mill: (low, high) of the empty interval along "x"/"y" through point (x, y, z)."""
        from cutsim.reports.measure import gap_at

        return gap_at(self.part, point, direction)

    def compare(self, design) -> dict:
        """Gouge/excess volumes and worst deviation against a design (path or Manifold)."""
        from cutsim.reports.measure import compare_design, load_solid

        return compare_design(self.part, load_solid(design) if isinstance(design, str) else design, self.stock)

    def check(self, **spec) -> dict:
        """Evaluate one check given as keyword arguments like a [[check]] table (kind=..., ...)."""
        from cutsim.testing import make_check_spec
        from cutsim.reports.checks import evaluate

        return evaluate(make_check_spec(self, spec), self)


MAX_PROGRAM_BYTES = 64 * 1024 * 1024  # a program file over 64 MiB is refused (README "Using it")


def read_program(path: str) -> str:
    """The text of the program file ``path``: UTF-8 (with or without BOM), else Windows-1250.
    Only regular files of at most MAX_PROGRAM_BYTES are read (a directory, a device such as
    /dev/zero or a named pipe is refused); every failure is a CutsimError ``PATH:0:0``."""
    def error(text):
        return CutsimError(path, 0, 0, f"cannot read the program: {text}")

    try:
        raw = read_bounded(path, MAX_PROGRAM_BYTES)
    except Unreadable as e:
        text = {"directory": "it is a directory", "special": "not a regular file (a device, pipe or socket)",
                "large": f"the file is larger than {MAX_PROGRAM_BYTES >> 20} MiB"}.get(e.kind, e.reason)
        raise error(text) from None
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        return raw.decode("cp1250", errors="replace")  # controllers of the region write Central European code pages


def default_start(setup: Setup, stock) -> tuple[float, float, float]:
    """A start position clear of the stock: 5 mm outside it radially and above it (lathe), or 10 mm
    above the middle of its top (mill)."""
    b = stock.bounding_box()
    lo, hi = b[:3], b[3:]
    if setup.machine.kind == "lathe":
        r = max(abs(lo[0]), abs(hi[0]), abs(lo[1]), abs(hi[1])) + 5.0
        return (2 * r if setup.machine.diameter_programming else r, 0.0, hi[2] + 5.0)
    return ((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, hi[2] + 10.0)


def interp_config(setup: Setup, start: tuple[float, float, float]) -> InterpConfig:
    """What the interpreter needs from the setup (``start``: the tool's position before the first block)."""
    m = setup.machine
    return InterpConfig(dialect=m.dialect, machine_kind=m.kind, diameter_programming=m.diameter_programming,
                        start=start, parameters=dict(setup.parameters), constants=dict(setup.constants),
                        max_blocks=setup.max_blocks, tool_radii={t.number: t.diameter / 2.0 for t in setup.tools},
                        tool_noses={t.number: (t.nose_radius, t.edge_position) for t in setup.tools if t.is_lathe_tool},
                        tool_widths={t.number: t.width for t in setup.tools if t.kind == "grooving"},
                        tool_faces=frozenset(t.number for t in setup.tools if t.is_lathe_tool and t.side == "face"),
                        axes=dict(setup.axes), m_functions=frozenset(setup.m_functions),
                        h_functions=frozenset(setup.h_functions), variables=dict(setup.variables),
                        transformations=frozenset(setup.transformations),
                        work_offsets=dict(setup.work_offsets), subprogram_path=tuple(setup.subprogram_path),
                        tool_names=dict(setup.tool_names),
                        external_subprograms=frozenset(setup.external_subprograms),
                        tool_table=setup.tool_table, parameter_file=setup.parameter_file,
                        thread_acceleration=setup.thread_acceleration)


def simulate(program: str, setup: str | Setup, *, tolerance: float | None = None, text: str | None = None,
             progress: Callable[[str, int, int], None] | None = None, checks: bool = True) -> Result:
    """Simulate ``program`` (a file path; or a name with ``text``) on ``setup`` (a path or a Setup).

    With ``checks`` (the default) the setup's [[check]] tables are evaluated and their records
    stored in ``result.report["checks"]`` (see docs/checks.md)."""
    from cutsim.kinematics import plan as make_plan
    from cutsim.reports import build_report
    from cutsim.stock import build_stock, remove

    if not isinstance(setup, Setup):
        setup = load_setup(setup)
    tol = tolerance if tolerance is not None else setup.tolerance
    if text is None:
        text = read_program(program)
    stock = build_stock(setup.stock, tol, setup.path, max_triangles=setup.max_triangles, where=setup.stock_where)
    start = setup.machine.start if setup.machine.start is not None else default_start(setup, stock)
    tick = progress or (lambda stage, i, n: None)
    tick("interpretation", 0, 1)  # a stage that takes over a second gets its "done (N s)" line
    prog = interpret(program, text, interp_config(setup, start))
    tick("interpretation", 1, 1)
    tick("planning", 0, 1)
    pl = make_plan(prog, setup.machine, setup.tools, tol)
    tick("planning", 1, 1)
    removal = remove(stock, setup.stock, pl.paths, tol, progress, max_triangles=setup.max_triangles)
    part = removal.part
    warnings = sorted(prog.warnings + pl.warnings + removal.warnings, key=lambda w: (w[0].line, w[0].col))
    report = build_report(program=os.path.basename(program), dialect=setup.machine.dialect, machine=setup.machine,
                          blocks=prog.blocks, moves=len(prog.moves), stock_volume=stock.volume(),
                          part_volume=part.volume(), cycle_time=pl.cycle_time, warnings=warnings,
                          final_position=pl.final_position, last_cut_position=prog.last_cut_position,
                          tolerance=tol, triangles=part.num_tri())
    result = Result(setup, prog, pl, stock, part, report)
    if checks and setup.checks:  # evaluated on the finished part; records in report.json
        report["checks"] = run_checks(setup, result, progress)
    return result


def run_checks(setup: Setup, result: "Result", progress: Callable[[str, int, int], None] | None = None
               ) -> list[dict]:
    """Evaluate the setup's [[check]] tables on ``result`` (records as in report.json);
    ``progress("checks", i, n)`` before each check and once at the end."""
    from cutsim.reports.checks import check_design, evaluate
    from cutsim.reports.measure import load_solid

    out = []
    for k, spec in enumerate(setup.checks):
        if progress:
            progress("checks", k, len(setup.checks))
        design = None
        if spec["kind"] == "design":
            try:
                design = load_solid(spec["path"])
            except Exception as e:  # noqa: BLE001 - an unreadable design file is bad input
                raise CutsimError(setup.path, spec["path_line"], spec["column"],
                                  f"[[check]] #{spec['index'] + 1} path: cannot use the design: {e}") from None
            out.append(check_design(spec, result, design))
            continue
        out.append(evaluate(spec, result))
    if progress:
        progress("checks", len(setup.checks), len(setup.checks))
    return out
