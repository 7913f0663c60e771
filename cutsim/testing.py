"""Assertions for tests of part programs (pytest or plain ``assert``)::

    import cutsim
    from cutsim.testing import assert_thread, assert_matches_design, assert_checks_pass

    def test_m27_thread():
        r = cutsim.simulate("thread.nc", "thread.toml", tolerance=0.01)
        assert_checks_pass(r)                       # every [[check]] of the setup
        assert_thread(r, z=(-6, 2), lead=1.5, root_diameter=26.177, phase=[0], phase_z=3)

Each raises AssertionError with a table of what was expected, what was measured and the
tolerance, so a failing test says why without a debugger. The keyword arguments are the keys of
the matching [[check]] table (docs/checks.md) and are validated the same way.
"""
from __future__ import annotations

from cutsim.reports.checks import check_design, evaluate, format_failures


def make_check_spec(result, spec: dict, kind: str | None = None) -> dict:
    """Validate ``spec`` (keys as in a [[check]] table) for ``result``'s machine; returns the
    normalised spec dict. Raises CutsimError for bad keys or values."""
    from cutsim.setup import check_spec

    table = {k: (list(v) if isinstance(v, tuple) else v) for k, v in spec.items() if v is not None}
    if kind is not None:
        table["kind"] = kind
    return check_spec(table, result.setup.machine.kind)


def _fail_if(record: dict) -> dict:
    if not record["passed"]:
        raise AssertionError("\n" + format_failures([record]))
    return record


def assert_checks_pass(result) -> None:
    """Every [[check]] of the setup passed (records in ``result.report["checks"]``)."""
    failed = [c for c in result.report.get("checks", []) if not c["passed"]]
    if failed:
        raise AssertionError("\n" + format_failures(failed))


def assert_thread(result, z, lead: float, *, starts: int = 1, hand: str = "right", root_diameter: float | None = None,
                  phase=None, phase_z: float | None = None, tolerance: float = 0.02, lead_tolerance: float = 0.005,
                  phase_tolerance: float = 2.0, angles: int = 36, name: str = "thread") -> dict:
    """The thread between z = (low, high) has this lead (mm/turn), number of starts, hand, and
    optionally root diameter (± tolerance) and start phases (degrees, with phase_z; see
    docs/checks.md). Returns the check record."""
    spec = make_check_spec(result, dict(z=z, lead=lead, starts=starts, hand=hand, root_diameter=root_diameter,
                                        phase=phase, phase_z=phase_z, tolerance=tolerance,
                                        lead_tolerance=lead_tolerance, phase_tolerance=phase_tolerance,
                                        angles=angles, name=name), "thread")
    return _fail_if(evaluate(spec, result))


def assert_matches_design(result, design, tol: float, *, max_gouge: float | None = None,
                          max_excess: float | None = None, name: str = "design") -> dict:
    """The part deviates from ``design`` (a mesh file path, a manifold3d.Manifold or a
    trimesh.Trimesh) by at most ``tol`` mm anywhere, and optionally the gouge / excess volumes
    stay under their limits (mm^3). Returns the check record."""
    from cutsim.reports.measure import load_solid

    if isinstance(design, str) or hasattr(design, "__fspath__"):
        path, man = str(design), load_solid(str(design))
    elif hasattr(design, "vertices") and hasattr(design, "faces"):
        from cutsim.stock.arrays import solid_of

        path = "<trimesh>"
        man = solid_of(design.vertices, design.faces)
    else:
        path, man = "<manifold>", design
    spec = {"kind": "design", "name": name, "line": 0, "path": path, "max_gouge": max_gouge,
            "max_excess": max_excess, "max_deviation": float(tol)}
    return _fail_if(check_design(spec, result, man))
