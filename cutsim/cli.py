"""The command line: ``cutsim simulate PROGRAM --setup SETUP.toml --out DIR``.

Exit status: 0 simulated and all checks passed; 1 simulated but a check failed or a warning was
escalated (``[simulation] fail_on_warning``); 2 the program, the setup, an option or the
environment is wrong (a message ``FILE:LINE:COL: error: TEXT`` on stderr, DIR unchanged);
3 an internal error (a bug in cutsim: please report it with the input); 130 interrupted (Ctrl-C),
143 terminated (SIGTERM), DIR unchanged. No command ends in a traceback.

Errors about options have no file: they read ``cutsim:0:0: error: --OPTION: TEXT`` (or
``PROGRAM: TEXT`` for the argument); errors about the output directory name it:
``DIR:0:0: error: --out: TEXT``. README "Using it" documents all of this.
"""
from __future__ import annotations

import errno
import os
import signal
import sys
import time

import click

from cutsim.interp.errors import CutsimError, location, printable
from cutsim.setup import MIN_TOLERANCE

FORMATS = ("stl", "3mf", "glb")
SETUP_HELP = "Setup TOML (docs/setup.md): machine and dialect, stock, tools, checks, [simulation] tolerance."
PROG = "cutsim"
_NO_ARGS_IS_HELP = getattr(click.exceptions, "NoArgsIsHelpError", ())  # () matches nothing (click 8.1)
# errors of the machine or the file system, not of cutsim: exit status 2
_ENV_ERRNOS = {errno.ENOSPC, errno.EDQUOT, errno.EACCES, errno.EPERM, errno.EROFS, errno.EIO, errno.EMFILE,
               errno.ENFILE, errno.ENOMEM, errno.EFBIG, errno.ENAMETOOLONG, errno.ENOTDIR, errno.EISDIR,
               errno.ENOENT, errno.ELOOP, errno.ENXIO, errno.ENODEV, errno.ETXTBSY, errno.EBUSY}


class _Progress:
    """Progress on stderr for the stages of a run (``progress(stage, i, n)``: step i of n) that last
    longer than DELAY seconds. On a terminal: a tqdm bar per stage. Otherwise (a log, a pipe, CI):
    plain single lines ``cutsim: STAGE i/n`` at most once every INTERVAL seconds per stage and a
    last ``cutsim: STAGE n/n done`` for a stage that printed a line, no control characters."""

    DELAY = 1.0
    INTERVAL = 5.0

    def __init__(self, enabled: bool, stream=None, tty: bool | None = None):
        self.enabled = enabled
        self.stream = stream if stream is not None else sys.stderr
        if tty is None:
            try:
                tty = bool(self.stream.isatty())
            except (AttributeError, ValueError, OSError):
                tty = False
        self.tty = tty
        self.bars = {}
        self.lines = {}  # stage -> [start time, time of the last line or None]
        self.t0 = time.monotonic()

    def __call__(self, stage: str, i: int, n: int) -> None:
        if not self.enabled:
            return
        if not self.tty:
            self._line(stage, i, n)
            return
        from tqdm import tqdm

        bar = self.bars.get(stage)
        if bar is None:
            bar = self.bars[stage] = tqdm(total=n, desc=stage, file=self.stream, delay=self.DELAY, leave=False,
                                          unit="step", dynamic_ncols=True)
        bar.update(max(0, i - bar.n))
        if i >= n:
            bar.close()
            del self.bars[stage]

    def _line(self, stage: str, i: int, n: int) -> None:
        now = time.monotonic()
        st = self.lines.get(stage)
        if st is None or (i == 0 and st[1] is None):
            st = self.lines[stage] = [now, None]
        done = i >= n
        if done:
            if st[1] is not None or now - st[0] >= self.DELAY:  # a stage that took a while: its time
                self._write(f"{PROG}: {stage} {n}/{n} done ({now - st[0]:.1f} s)")
            del self.lines[stage]
            return
        if now - st[0] >= self.DELAY and (st[1] is None or now - st[1] >= self.INTERVAL):
            st[1] = now
            self._write(f"{PROG}: {stage} {i}/{n}")

    def _write(self, text: str) -> None:
        try:
            self.stream.write(text + "\n")
            self.stream.flush()
        except (OSError, ValueError):
            pass

    def close(self):
        for bar in self.bars.values():
            bar.close()
        self.bars = {}
        self.lines = {}


class _Terminated(KeyboardInterrupt):
    """SIGTERM, raised like Ctrl-C so the same clean-up runs (exit status 143)."""


def _on_sigterm(signum, frame):
    raise _Terminated()


def _fail(e: BaseException, where: str, written: bool | None = None) -> int:
    """Print the one-line message for ``e`` and return the exit status (module doc)."""
    if isinstance(e, click.exceptions.Abort) and isinstance(e.__cause__, KeyboardInterrupt):
        e = e.__cause__
    if isinstance(e, CutsimError):
        click.echo(str(e), err=True)
        return 2
    if isinstance(e, (KeyboardInterrupt, click.exceptions.Abort)):
        what = "terminated" if isinstance(e, _Terminated) else "interrupted"
        tail = "" if written is None else "; the output was written" if written else "; nothing written"
        click.echo(f"{PROG}: {what}{tail}", err=True)
        return 143 if isinstance(e, _Terminated) else 130
    if isinstance(e, OSError) and e.errno == errno.EPIPE:
        _silence_stdout()
        return 141
    if isinstance(e, MemoryError):
        click.echo(f"{location(where, 0, 0)}: error: out of memory", err=True)
        return 2
    if isinstance(e, OSError) and (e.filename or e.errno in _ENV_ERRNOS):
        path = e.filename if isinstance(e.filename, str) and e.filename else where
        click.echo(f"{location(path, 0, 0)}: error: {printable(str(e.strerror or e))}", err=True)
        return 2
    if os.environ.get("CUTSIM_DEBUG"):
        import traceback

        traceback.print_exception(e)
    click.echo(f"{location(where, 0, 0)}: error: internal error in cutsim ({type(e).__name__}: {printable(str(e))}); "
               "please report it with the program and setup", err=True)
    return 3


def _silence_stdout():
    """The reader of stdout went away (``cutsim moves ... | head``): no more writes, no noise."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError, AttributeError):
        pass


def _param_hint(param) -> str:
    if isinstance(param, click.Option):
        longs = [o for o in param.opts if o.startswith("--")]
        return (longs or param.opts)[0]
    return param.human_readable_name if param is not None else ""


def _usage_text(e: click.exceptions.UsageError) -> str:
    """click's usage errors in cutsim's form: ``--OPTION: TEXT`` or ``PROGRAM: TEXT``."""
    param = getattr(e, "param", None)
    hint = getattr(e, "param_hint", None)
    if isinstance(hint, (list, tuple)):
        hint = " / ".join(hint)
    hint = hint or (_param_hint(param) if param is not None else "")
    if isinstance(e, click.exceptions.MissingParameter) and hint:
        kind = "argument" if isinstance(param, click.Argument) else "option"
        text = f"{hint}: missing (a required {kind})"
    elif isinstance(e, click.exceptions.BadParameter) and hint:
        text = f"{hint}: {e.message}"
    else:
        text = e.format_message()
    return " ".join(text.split()).rstrip(".")


class _Main(click.Group):
    """The ``cutsim`` group: every command runs under one guard, so nothing ends in a traceback
    and click's usage errors come out as ``cutsim:0:0: error: ...`` with exit status 2."""

    def main(self, args=None, prog_name=None, complete_var=None, standalone_mode=True, **extra):
        if not standalone_mode:
            return super().main(args, prog_name, complete_var, standalone_mode=False, **extra)
        old = None
        try:
            old = signal.signal(signal.SIGTERM, _on_sigterm)
        except ValueError:  # not the main thread
            pass
        try:
            code = self._guarded(args, PROG, complete_var, extra)  # "cutsim" under python -m too
        finally:
            if old is not None:
                signal.signal(signal.SIGTERM, old)
        try:
            sys.stdout.flush()
        except OSError:
            _silence_stdout()
        sys.exit(code)

    def _guarded(self, args, prog_name, complete_var, extra) -> int:
        try:
            rv = super().main(args, prog_name, complete_var, standalone_mode=False, **extra)
            return rv if isinstance(rv, int) else 0
        except SystemExit:
            raise
        except _NO_ARGS_IS_HELP as e:  # `cutsim` alone: the help (click >= 8.2)
            e.show()
            return e.exit_code
        except click.exceptions.UsageError as e:
            click.echo(f"{PROG}:0:0: error: {_usage_text(e)}", err=True)
            return 2
        except click.exceptions.ClickException as e:
            click.echo(f"{PROG}:0:0: error: {' '.join(e.format_message().split())}", err=True)
            return 2
        except click.exceptions.Exit as e:
            return e.exit_code
        except BaseException as e:  # noqa: BLE001 - no input may end in a traceback
            return _fail(e, PROG)


def _nonempty(ctx, param, value):
    if value == "":
        raise click.BadParameter("the file name is empty", ctx=ctx, param=param)
    return value


@click.group(cls=_Main, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="cutsim")
def main():
    """cutsim: simulate a CNC part program on its stock and measure the result."""


@main.command()
@click.argument("program", type=click.Path(), callback=_nonempty)
@click.option("--setup", "setup_path", required=True, type=click.Path(), callback=_nonempty, help=SETUP_HELP)
@click.option("--out", "out_dir", required=True, type=click.Path(),
              help="Output directory (created when missing) for the part and report.json. Written as one "
                   "transaction when the run succeeds: cutsim's files of an earlier run are replaced or "
                   "removed, other files in DIR are kept; when the run fails DIR is left as it was.")
@click.option("--tolerance", type=float, default=None,
              help="Chordal tolerance in mm, 0.0001 to 1 (overrides the setup's [simulation] tolerance).")
@click.option("--images", is_flag=True, help="Also write off-screen PNG views and report.html.")
@click.option("--format", "fmt", type=click.Choice(FORMATS), default="stl", show_default=True,
              help="File format of the part: DIR/part.stl, part.3mf or part.glb.")
@click.option("--quiet", "-q", is_flag=True,
              help="No progress and no summary line (warnings, failed checks and errors are still printed).")
def simulate(program, setup_path, out_dir, tolerance, images, fmt, quiet):
    """Simulate PROGRAM and write DIR/part.<format> and DIR/report.json.

    The summary line goes to stdout; warnings, failed checks, errors and progress go to stderr."""
    return run_simulate(program, setup_path, out_dir, tolerance, images, quiet, fmt)


def run_simulate(program, setup_path, out_dir, tolerance, images=False, quiet=False, fmt="stl") -> int:
    """``cutsim simulate`` without click: prints what the command prints, returns its exit status."""
    progress = _Progress(not quiet)
    out = None
    try:
        import cutsim
        from cutsim.output import Output
        from cutsim.reports.report import mesh_arrays, part_bytes, report_bytes

        if tolerance is not None and not (MIN_TOLERANCE <= tolerance <= 1.0):
            raise CutsimError(PROG, 0, 0, f"--tolerance: {tolerance:g} is not between 0.0001 and 1 mm")
        names = [f"part.{fmt}", "report.json"] + (["report.html"] if images else [])
        out = Output(out_dir, names)  # an unusable DIR is reported before the simulation
        result = cutsim.simulate(program, setup_path, tolerance=tolerance, progress=progress)
        files = {}
        v, f = mesh_arrays(result.part)
        files[f"part.{fmt}"] = part_bytes(v, f, fmt)
        files["report.json"] = report_bytes(result.report)
        if images:
            from cutsim.reports.html import report_html
            from cutsim.reports.images import render_images  # pyvista only when asked

            captions = {}
            pngs = render_images(result, progress, captions)
            files.update(pngs)
            files["report.html"] = report_html(result.report, pngs, captions=captions, setup=result.setup,
                                               order=list(pngs))
        out.commit(files)
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
            click.echo(f"{printable(rep['program'])}: {rep['blocks']} blocks, {rep['moves']} moves, removed "
                       f"{rep['removed_volume']:.3f} mm^3, {len(rep['warnings'])} warning(s) -> {printable(str(out_dir))}")
        if failed or (result.setup.fail_on_warning and rep["warnings"]):
            return 1
        return 0
    except BaseException as e:  # noqa: BLE001 - no input may end in a traceback
        progress.close()
        written = out is not None and out.committed
        if out is not None:
            out.abort()
        if isinstance(e, SystemExit):
            raise
        return _fail(e, program, written)


@main.command()
@click.argument("program", type=click.Path(), callback=_nonempty)
@click.option("--setup", "setup_path", required=True, type=click.Path(), callback=_nonempty,
              help="Setup TOML (docs/setup.md): the dialect and what the program reads from the machine "
                   "(kind, diameter programming, start position, parameters, variables, work offsets, tools).")
def moves(program, setup_path):
    """Print the canonical moves of PROGRAM (the interpreter's transcript) on stdout.

    Nothing is swept and nothing is written; errors go to stderr."""
    try:
        import cutsim
        from cutsim.interp import interpret
        from cutsim.interp.canon import transcript_lines

        setup = cutsim.load_setup(setup_path)
        text = cutsim.read_program(program)
        m = setup.machine
        start = m.start if m.start is not None else cutsim.default_start(setup, _stock(setup))
        prog = interpret(program, text, cutsim.interp_config(setup, start))  # errors before any output
        chunk: list[str] = []
        for line in transcript_lines(prog):  # never the whole transcript in memory (~170 MB at 1M moves)
            chunk.append(line)
            if len(chunk) == 8192:
                click.echo("".join(chunk), nl=False)
                chunk.clear()
        click.echo("".join(chunk), nl=False)
        sys.stdout.flush()
    except BaseException as e:  # noqa: BLE001 - no input may end in a traceback
        if isinstance(e, SystemExit):
            raise
        return _fail(e, program)
    return 0


def _stock(setup):
    from cutsim.stock import build_stock

    return build_stock(setup.stock, setup.tolerance, setup.path, max_triangles=setup.max_triangles,
                       where=setup.stock_where)


from cutsim.batch import batch_command  # noqa: E402  (cutsim batch; docs/batch.md)

main.add_command(batch_command)


if __name__ == "__main__":  # pragma: no cover
    main()
