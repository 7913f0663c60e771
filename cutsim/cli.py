"""The command line: ``cutsim simulate PROGRAM --setup SETUP.toml --out DIR``.

Exit status: 0 simulated and all checks passed; 1 simulated but a check failed or a warning was
escalated (``[simulation] fail_on_warning``); 2 the program or setup is wrong (nothing is written);
3 an internal error (a bug in cutsim: please report it with the input).
"""
from __future__ import annotations

import sys
import time

import click

from cutsim.interp.errors import CutsimError

FORMATS = ("stl", "3mf", "glb")


class _Progress:
    """Progress on stderr for runs longer than about a second (tqdm bars, one per stage)."""

    def __init__(self, enabled: bool):
        self.enabled = enabled
        self.bars = {}
        self.t0 = time.monotonic()

    def __call__(self, stage: str, i: int, n: int) -> None:
        if not self.enabled:
            return
        from tqdm import tqdm

        bar = self.bars.get(stage)
        if bar is None:
            bar = self.bars[stage] = tqdm(total=n, desc=stage, file=sys.stderr, delay=1.0, leave=False,
                                          unit="step", dynamic_ncols=True)
        bar.update(i - bar.n)
        if i >= n:
            bar.close()

    def close(self):
        for bar in self.bars.values():
            bar.close()


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="cutsim")
def main():
    """cutsim: simulate a CNC part program on its stock and measure the result."""


@main.command()
@click.argument("program", type=click.Path(dir_okay=False))
@click.option("--setup", "setup_path", required=True, type=click.Path(dir_okay=False),
              help="Setup TOML: machine, stock, tools, tolerance.")
@click.option("--out", "out_dir", required=True, type=click.Path(file_okay=False),
              help="Output directory for part.stl and report.json.")
@click.option("--tolerance", type=float, default=None, help="Chordal tolerance in mm (overrides the setup).")
@click.option("--images", is_flag=True, help="Also write off-screen PNG views and report.html.")
@click.option("--format", "fmt", type=click.Choice(FORMATS), default="stl", show_default=True,
              help="File format of the part: DIR/part.stl, part.3mf or part.glb.")
@click.option("--quiet", "-q", is_flag=True, help="No progress and no summary.")
def simulate(program, setup_path, out_dir, tolerance, images, fmt, quiet):
    """Simulate PROGRAM and write DIR/part.stl and DIR/report.json."""
    sys.exit(run_simulate(program, setup_path, out_dir, tolerance, images, quiet, fmt))


def run_simulate(program, setup_path, out_dir, tolerance, images=False, quiet=False, fmt="stl") -> int:
    import cutsim
    from cutsim.reports.report import mesh_arrays, part_bytes, report_bytes, write_outputs

    progress = _Progress(not quiet)
    try:
        if tolerance is not None and not (1e-5 <= tolerance <= 1.0):
            raise CutsimError(setup_path, 0, 0, f"--tolerance {tolerance} must be between 0.00001 and 1 mm")
        result = cutsim.simulate(program, setup_path, tolerance=tolerance, progress=progress)
        files = {}
        v, f = mesh_arrays(result.part)
        files[f"part.{fmt}"] = part_bytes(v, f, fmt)
        files["report.json"] = report_bytes(result.report)
        if images:
            from cutsim.reports.html import report_html
            from cutsim.reports.images import render_images  # pyvista only when asked

            pngs = render_images(result)
            files.update(pngs)
            files["report.html"] = report_html(result.report, pngs)
        write_outputs(out_dir, files)
    except CutsimError as e:
        progress.close()
        click.echo(str(e), err=True)
        return 2
    except KeyboardInterrupt:
        progress.close()
        click.echo("cutsim: interrupted; nothing written", err=True)
        return 130
    except Exception as e:  # noqa: BLE001 - no input may end in a traceback
        progress.close()
        click.echo(f"{program}:0:0: error: internal error in cutsim ({type(e).__name__}: {e}); "
                   "please report it with the program and setup", err=True)
        return 3
    progress.close()
    rep = result.report
    from cutsim.reports.report import warning_text

    for w in rep["warnings"]:
        click.echo(warning_text(w), err=True)
    failed = [c for c in rep.get("checks", []) if not c.get("passed", True)]
    if failed:
        from cutsim.reports.checks import format_failures

        click.echo(format_failures(failed), err=True)
    if not quiet:
        click.echo(f"{rep['program']}: {rep['blocks']} blocks, {rep['moves']} moves, removed "
                   f"{rep['removed_volume']:.3f} mm^3, {len(rep['warnings'])} warning(s) -> {out_dir}", err=True)
    if failed or (result.setup.fail_on_warning and rep["warnings"]):
        return 1
    return 0


@main.command()
@click.argument("program", type=click.Path(dir_okay=False))
@click.option("--setup", "setup_path", required=True, type=click.Path(dir_okay=False))
def moves(program, setup_path):
    """Print the canonical moves of PROGRAM (the interpreter's transcript)."""
    import cutsim
    from cutsim.interp import interpret, transcript

    try:
        setup = cutsim.load_setup(setup_path)
        text = cutsim.read_program(program)
        m = setup.machine
        start = m.start if m.start is not None else cutsim.default_start(setup, _stock(setup))
        click.echo(transcript(interpret(program, text, cutsim.interp_config(setup, start))), nl=False)
    except CutsimError as e:
        click.echo(str(e), err=True)
        sys.exit(2)


def _stock(setup):
    from cutsim.stock import build_stock

    return build_stock(setup.stock, setup.tolerance, setup.path)


if __name__ == "__main__":  # pragma: no cover
    main()
