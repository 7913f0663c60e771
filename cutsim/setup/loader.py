"""Reading a setup file: the bytes (bounded, UTF-8), the TOML, then each table in a fixed order
(simulation, machine, parameters, stock, tools, checks, variables, work offsets) so the first
problem reported is always the same one."""
from __future__ import annotations

import os
import re
import stat
import tomllib

from cutsim.interp.errors import CutsimError

from .checks import read_checks
from .limits import MAX_SETUP_BYTES, show
from .machine import read_machine, read_parameters, read_variables, read_work_offsets
from .model import Setup
from .reader import Locator, Reader
from .simulation import read_simulation
from .stock import read_stock
from .tools import read_tools

_TABLES = ("machine", "parameters", "stock", "tool", "simulation", "check", "variables", "work_offsets")


def _check_tables(loc: Locator, data: dict) -> None:
    """Only known tables, each a table (or an array of tables for [[tool]] and [[check]])."""
    for top in data:
        if top not in _TABLES:
            line, col = loc.locate(top, None, None)
            raise CutsimError(loc.path, line, col, f"unknown table [{top}]")
    for top in ("machine", "parameters", "stock", "simulation", "variables", "work_offsets"):
        if top in data and not isinstance(data[top], dict):
            raise CutsimError(loc.path, *loc.locate(top, None, None),
                              f"[{top}] must be a table, not {show(data[top])}")
    for top in ("tool", "check"):
        if top in data and isinstance(data[top], list):
            for i, t in enumerate(data[top]):
                if not isinstance(t, dict):
                    raise CutsimError(loc.path, *loc.locate(top, None, i),
                                      f"[[{top}]] #{i + 1} must be a table, not {show(t)}")
    if "machine" not in data:
        raise CutsimError(loc.path, 1, 1, "the setup needs a [machine] table")


def load(path: str, text: str, data: dict) -> Setup:
    """The Setup of the TOML ``data`` read from ``text`` (the file ``path``)."""
    loc = Locator(path, text)
    _check_tables(loc, data)
    sim = read_simulation(loc, data.get("simulation"))
    m = read_machine(loc, data["machine"])
    params = read_parameters(loc, data["parameters"]) if "parameters" in data else {}
    if "stock" not in data:
        raise CutsimError(path, 1, 1, "the setup needs a [stock] table")
    stock, stock_where = read_stock(loc, Reader(loc, data["stock"], "stock"), sim)
    tools, tool_names = read_tools(loc, data.get("tool", []), m.spec.kind)
    checks = read_checks(loc, data.get("check", []), m.spec.kind)
    variables = read_variables(loc, data.get("variables", {}), m.spec.dialect)
    work_offsets = read_work_offsets(loc, data.get("work_offsets", {}), m.spec.dialect)
    return Setup(path, m.spec, stock, tools, params, m.constants, sim.tolerance, sim.fail_on_warning, checks,
                 sim.max_blocks, sim.max_triangles, stock_where, axes=m.axes, m_functions=m.m_functions,
                 h_functions=m.h_functions, subprogram_path=m.subprogram_path, variables=variables,
                 work_offsets=work_offsets, tool_names=tool_names, transformations=m.transformations,
                 external_subprograms=m.external_subprograms, tool_table=m.tool_table,
                 parameter_file=m.parameter_file, thread_acceleration=m.thread_acceleration)


def load_setup(path: str) -> Setup:
    """Read and validate a setup file. Raises CutsimError (exit status 2 in the CLI)."""
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except (OSError, ValueError) as e:
        raise CutsimError(path, 0, 0, f"cannot read the setup: {getattr(e, 'strerror', None) or e}") from None
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            raise CutsimError(path, 0, 0, "cannot read the setup: not a regular file")
        with os.fdopen(os.dup(fd), "rb") as f:
            raw = f.read(MAX_SETUP_BYTES + 1)
    except OSError as e:
        raise CutsimError(path, 0, 0, f"cannot read the setup: {e.strerror}") from None
    finally:
        os.close(fd)
    if len(raw) > MAX_SETUP_BYTES:
        raise CutsimError(path, 0, 0, f"the setup is larger than {MAX_SETUP_BYTES >> 20} MiB")
    try:
        text = raw.decode("utf-8-sig")  # a byte order mark is accepted
    except UnicodeDecodeError as e:
        bom = 3 if raw.startswith(b"\xef\xbb\xbf") else 0
        at = e.start + bom  # the decoder counts from after the byte order mark
        ls = raw.rfind(b"\n", 0, at) + 1
        head = raw[max(ls, bom):at].decode("utf-8")
        raise CutsimError(path, raw.count(b"\n", 0, at) + 1, len(head) + 1,
                          f"the setup is not UTF-8 text (byte 0x{raw[at]:02x} at offset {at})") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        line = getattr(e, "lineno", 0) or 0
        col = getattr(e, "colno", 0) or 0
        msg = getattr(e, "msg", str(e))
        where = re.search(r"\s*\(at line (\d+), column (\d+)\)$", msg)  # Python < 3.14: only in the text
        if where:
            line, col = line or int(where.group(1)), col or int(where.group(2))
            msg = msg[:where.start()]
        end = re.search(r"\s*\(at end of document\)$", msg)
        if end or not line:  # the error is where the text ends
            msg = msg[:end.start()] + " (at the end of the file)" if end else msg
            line, col = text.count("\n") + 1, len(text) - (text.rfind("\n") + 1) + 1
        raise CutsimError(path, line, col, f"not valid TOML: {msg}") from None
    except ValueError as e:  # tomllib's int() of a number with more digits than Python converts
        line, col = huge_number_at(text)
        reason = str(e).split(";")[0]  # without Python's advice (sys.set_int_max_str_digits)
        raise CutsimError(path, line, col, f"not valid TOML: a number with too many digits ({reason})") from None
    except RecursionError:  # tomllib reads nested arrays and inline tables recursively
        raise CutsimError(path, 1, 1, "arrays or inline tables are nested too deeply") from None
    return load(path, text, data)


def huge_number_at(text: str) -> tuple[int, int]:
    """(line, column) of the first run of more than 4300 digits (Python's limit for int of a string,
    which tomllib raises as a plain ValueError), or the start of the text."""
    m = re.search(r"[0-9_]{4300,}", text)
    if not m:
        return 1, 1
    return text.count("\n", 0, m.start()) + 1, m.start() - (text.rfind("\n", 0, m.start()) + 1) + 1
