"""RS274NGC as LinuxCNC 2.9 reads it (files .ngc, .nc, .tap): one package on the shared executor.

``syntax`` parses lines (words, expressions, O-words), ``values`` holds the parameters and
evaluates expressions, ``machine`` runs a block on ``core.Interpreter`` (modes, motion),
``offsets`` and ``cycles`` the coordinate systems and canned cycles, ``flow`` the O-word control
flow, ``files`` the setup's tool table and parameter file. docs/dialects/rs274ngc.md says what is
simulated, what is refused and where the simulator assumes.
"""
from __future__ import annotations

from cutsim.interp.canon import Program
from cutsim.interp.core.modal import InterpConfig

from . import files
from .flow import Runner, load_unit
from .machine import Ngc
from .predefined import install
from .values import Evaluator, Parameters


def interpret(name: str, text: str, cfg: InterpConfig) -> Program:
    initial = files.parameter_file(cfg.parameter_file) if cfg.parameter_file else {}
    tools = files.tool_table(cfg.tool_table) if cfg.tool_table else {}
    params = Parameters(name, initial)
    machine = Ngc(name, cfg, params, tools)
    install(machine)
    unit = load_unit(name, text)
    Runner(machine, Evaluator(params, name), unit, tuple(cfg.subprogram_path)).run()
    machine.program.blocks = machine.executed
    machine.program.final_position = tuple(machine.pos)
    return machine.program
