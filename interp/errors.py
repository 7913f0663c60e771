"""The one error type of cutsim: a message tied to a file, line and column."""
from __future__ import annotations

import unicodedata

# Characters that would break a one-line message or cannot be written to a terminal: control
# characters (newline, tab, escape ...), line and paragraph separators, undecodable bytes (a file
# name's invalid UTF-8, held as lone surrogates).
_ESCAPED = frozenset({"Cc", "Zl", "Zp", "Cs"})


def printable(text: str) -> str:
    """``text`` with each character that would break the line (see _ESCAPED) escaped as Python's
    repr escapes it (``\\n``, ``\\t``, ``\\x1b``, ``\\u2028``, ``\\udcff``): a file named with a
    newline still gives one ``FILE:LINE:COL: error: TEXT`` line. Other characters stay as they are."""
    if text.isprintable():
        return text
    return "".join(repr(c)[1:-1] if unicodedata.category(c) in _ESCAPED else c for c in text)


def location(file, line: int, col: int) -> str:
    """``FILE:LINE:COL`` as errors and warnings print it, the file name made ``printable``."""
    return f"{printable(str(file))}:{line}:{col}"


class CutsimError(Exception):
    """An error in a user's input (program or setup), reported as ``FILE:LINE:COL: error: TEXT``
    on one line (file name and text ``printable``).

    ``line`` and ``col`` are 1-based; 0 means "the whole file" (e.g. it cannot be read).
    """

    def __init__(self, program: str, line: int, col: int, message: str):
        super().__init__(message)
        self.program = program
        self.line = line
        self.col = col
        self.message = message

    def __str__(self) -> str:
        return f"{location(self.program, self.line, self.col)}: error: {printable(self.message)}"
