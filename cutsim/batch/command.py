"""``cutsim batch MANIFEST --out DIR``: the command line of the batch (docs/batch.md). The closing
summary goes to stdout; progress and errors go to stderr."""
from __future__ import annotations

import click

from cutsim.interp.errors import CutsimError
from cutsim.setup import MIN_TOLERANCE

from .records import DEFAULT_REFERENCE_TOL, PASSED
from .run import DEFAULT_MEMORY, DEFAULT_TIMEOUT, run_batch


@click.command("batch")


@click.argument("manifest", type=click.Path())


@click.option("--out", "out_dir", required=True, type=click.Path(),
              help="Output directory: DIR/<job>/, summary.json, timings.json, junit.xml, index.html.")


@click.option("--jobs", "-j", "n_jobs", type=click.IntRange(1, 4096), default=None,
              help="Jobs at a time on the local pool (default: the number of cores; ignored with --scheduler).")


@click.option("--scheduler", default=None, help="Run on a Dask cluster: the scheduler's address, tcp://HOST:8786.")


@click.option("--images", is_flag=True, help="Also write PNG views and report.html per job (thumbnails in index.html).")


@click.option("--resume", is_flag=True, help="Skip jobs with a finished result of the same inputs, cutsim and options.")


@click.option("--tolerance", type=float, default=None, help="Chordal tolerance in mm, 0.0001 to 1, for jobs that set none (else the setup's).")


@click.option("--timeout", type=click.FloatRange(min=0, min_open=True), default=None,
              help=f"Time limit per job in s for jobs that set none (default {DEFAULT_TIMEOUT:g}).")


@click.option("--memory", type=click.IntRange(min=0), default=None,
              help=f"Address-space limit per job in MiB for jobs that set none (default {DEFAULT_MEMORY}; 0: none).")


@click.option("--reference-dir", type=click.Path(), default=None,
              help="Regression mode: compare each part with REFDIR/<job>/part.stl (an earlier batch's DIR).")


@click.option("--reference-tol", type=click.FloatRange(min=0), default=None,
              help=f"Regression mode: allowed symmetric difference in mm^3 (default {DEFAULT_REFERENCE_TOL:g}).")


@click.option("--quiet", "-q", is_flag=True, help="No progress and no closing summary.")


@click.pass_context
def batch_command(ctx, manifest, out_dir, n_jobs, scheduler, images, resume, tolerance, timeout, memory,
                  reference_dir, reference_tol, quiet):
    """Verify every job of MANIFEST (a TOML or CSV list, or a folder of PROGRAM + PROGRAM.toml).

    The closing summary goes to stdout; progress and errors go to stderr (docs/batch.md)."""
    try:
        if tolerance is not None and not (MIN_TOLERANCE <= tolerance <= 1.0):
            raise CutsimError("cutsim", 0, 0, f"--tolerance: {tolerance:g} is not between 0.0001 and 1 mm")
        summary = run_batch(manifest, out_dir, scheduler=scheduler, workers=n_jobs, tolerance=tolerance,
                            timeout=timeout, memory=memory, images=images, resume=resume,
                            reference_dir=reference_dir, reference_tol=reference_tol, progress=not quiet)
    except CutsimError as e:
        click.echo(str(e), err=True)
        ctx.exit(2)
    except OSError as e:  # writing DIR's files: disk full, permissions
        click.echo(f"{e.filename or out_dir}:0:0: error: {e.strerror or e}", err=True)
        ctx.exit(2)
    except KeyboardInterrupt as e:  # Ctrl-C; SIGTERM too under the cutsim group (cli._Terminated)
        term = type(e).__name__ == "_Terminated"
        click.echo(f"cutsim batch: {'terminated' if term else 'interrupted'}; finished jobs are kept in {out_dir} "
                   "(--resume continues)", err=True)
        ctx.exit(143 if term else 130)
    if not quiet:
        c = summary["counts"]
        click.echo(f"cutsim batch: {summary['total']} jobs, " + ", ".join(f"{v} {k}" for k, v in c.items())
                   + f" in {summary.timings['wall_seconds']:.1f} s -> {out_dir}/index.html")
        for j in summary["jobs"]:
            if j["status"] != PASSED:
                click.echo(f"  {j['name']}: {j['status']}: {j['message']}")
    ctx.exit(summary.exit_status)
