"""The one error type of cutsim: a message tied to a file, line and column."""
from __future__ import annotations


class CutsimError(Exception):
    """An error in a user's input (program or setup), reported as ``FILE:LINE:COL: error: TEXT``.

    ``line`` and ``col`` are 1-based; 0 means "the whole file" (e.g. it cannot be read).
    """

    def __init__(self, program: str, line: int, col: int, message: str):
        super().__init__(message)
        self.program = program
        self.line = line
        self.col = col
        self.message = message

    def __str__(self) -> str:
        return f"{self.program}:{self.line}:{self.col}: error: {self.message}"
