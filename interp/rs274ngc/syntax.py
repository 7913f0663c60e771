"""RS274NGC lines as LinuxCNC 2.9 reads them: words, parameter settings, O-words, expressions.

A line is parsed once into a ``Line`` whose values are expression trees (tuples, see ``parse_expr``):
the interpreter evaluates them each time the line runs (loops, subroutines). Blanks are ignored
outside comments and case does not matter (``G 1 x 1 0 . 5`` is ``G1 X10.5``); comments are
``( ... )`` and ``;`` to the end of the line.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field

from cutsim.interp.errors import CutsimError

# Letters that open a word (LinuxCNC 2.9; U V W A B C are axes the simulator has not: refused where used).
WORD_LETTERS = set("abcdefghijklmnpqrstuvwxyz")
FUNCTIONS = ("abs", "acos", "asin", "atan", "cos", "exp", "fix", "fup", "ln", "round", "sin", "sqrt", "tan")
# Binary operators by precedence, as LinuxCNC ranks them (higher binds tighter).
BINARY = {"**": 6, "*": 5, "/": 5, "mod": 5, "+": 4, "-": 4,
          "eq": 3, "ne": 3, "gt": 3, "ge": 3, "lt": 3, "le": 3, "and": 2, "or": 2, "xor": 2}
OWORD_KEYWORDS = ("sub", "endsub", "call", "do", "while", "endwhile", "if", "elseif", "else", "endif",
                  "repeat", "endrepeat", "break", "continue", "return")
_NUMBER = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)")
_NAME_OPS = sorted((k for k in BINARY if k.isalpha()), key=len, reverse=True)


@dataclass
class Line:
    """One program line. ``words``: (letter, expression, column); ``assigns``: (parameter reference,
    expression, column), applied after the line's words are read; ``oword``: (label, keyword,
    argument expressions, column) for an O-word line."""

    lineno: int
    delete: bool = False
    words: list = field(default_factory=list)
    assigns: list = field(default_factory=list)
    oword: tuple | None = None
    messages: list = field(default_factory=list)  # (MSG, ...) texts


class Reader:
    """Parses one line's compacted text (blanks out of comments removed, lower case) with a map from
    each character back to its column in the original line."""

    def __init__(self, program: str, lineno: int, raw: str):
        self.program, self.lineno = program, lineno
        self.text, self.cols, self.comments = compact(program, lineno, raw)
        self.i = 0

    def error(self, message: str, i: int | None = None) -> CutsimError:
        i = self.i if i is None else i
        col = self.cols[i] if i < len(self.cols) else (self.cols[-1] + 1 if self.cols else 1)
        return CutsimError(self.program, self.lineno, col, message)

    def peek(self, n: int = 1) -> str:
        return self.text[self.i:self.i + n]

    def expect(self, s: str, what: str) -> None:
        if self.peek(len(s)) != s:
            raise self.error(f"expected {what}")
        self.i += len(s)

    # -- values --------------------------------------------------------------------------------------
    def real_value(self):
        """A number, ``[expression]``, ``#parameter`` or ``function[...]``, optionally signed."""
        c = self.peek()
        if c and c in "+-" and (self.peek(2)[1:2] in ("[", "#") or self.peek(2)[1:2].isalpha()):
            self.i += 1
            v = self.real_value()
            return ("neg", v) if c == "-" else v
        if c == "[":
            self.i += 1
            v = self.expression()
            self.expect("]", "']' closing the expression")
            return v
        if c == "#":
            return ("par", self.parameter_ref())
        if c.isalpha():
            return self.function()
        m = _NUMBER.match(self.text, self.i)
        if not m:
            raise self.error("bad number or expression")
        j = m.end()
        if j < len(self.text) and self.text[j] == ".":
            raise self.error(f"malformed number '{self.text[self.i:j + 1]}'")
        self.i = j
        return ("num", float(m.group()))

    def parameter_ref(self):
        """After ``#``: a numbered parameter (``#12``, ``#[#1+2]``, ``##1``) or a named one (``#<name>``)."""
        start = self.i
        self.i += 1
        if self.peek() == "<":
            end = self.text.find(">", self.i)
            if end < 0:
                raise self.error("named parameter without its closing '>'", start)
            name = self.text[self.i + 1:end]
            if not name:
                raise self.error("empty parameter name", start)
            self.i = end + 1
            return ("name", name)
        if self.peek() == "#" or self.peek() == "[":
            return ("num_of", self.real_value())
        m = re.compile(r"[0-9]+").match(self.text, self.i)
        if not m:
            raise self.error("'#' must be followed by a parameter number, #<name> or [expression]", start)
        self.i = m.end()
        return ("index", int(m.group()))

    def function(self):
        start = self.i
        for name in ("exists",) + FUNCTIONS:
            if self.text.startswith(name, self.i):
                self.i += len(name)
                if self.peek() != "[":
                    raise self.error(f"'{name}' must be followed by '['", start)
                self.i += 1
                if name == "exists":
                    if self.peek(2) != "#<":
                        raise self.error("EXISTS takes a named parameter #<name>")
                    ref = self.parameter_ref()
                    self.expect("]", "']' after EXISTS[#<name>")
                    return ("exists", ref[1])
                arg = self.expression()
                self.expect("]", f"']' closing {name.upper()}[...]")
                if name == "atan":
                    self.expect("/[", "ATAN[y]/[x]")
                    arg2 = self.expression()
                    self.expect("]", "']' closing ATAN[y]/[x]")
                    return ("atan", arg, arg2, self.cols[start])
                return ("fn", name, arg, self.cols[start])
        raise self.error("unknown function or word in an expression", start)

    def binary_op(self):
        for op in ("**", "*", "/", "+", "-"):
            if self.text.startswith(op, self.i):
                return op
        for op in _NAME_OPS:
            if self.text.startswith(op, self.i):
                return op
        return None

    def expression(self):
        """Operands and binary operators up to the closing bracket, by LinuxCNC's precedence (all
        left-associative, ``2**3**2`` is 64)."""
        operands = [self.real_value()]
        ops: list[tuple[str, int]] = []
        while self.peek() != "]":
            if self.i >= len(self.text):
                raise self.error("expression without its closing ']'")
            op = self.binary_op()
            if op is None:
                raise self.error("expected an operator in the expression")
            col = self.cols[self.i]
            self.i += len(op)
            while ops and BINARY[ops[-1][0]] >= BINARY[op]:
                o, c = ops.pop()
                b = operands.pop()
                operands.append(("bin", o, operands.pop(), b, c))
            ops.append((op, col))
            operands.append(self.real_value())
        while ops:
            o, c = ops.pop()
            b = operands.pop()
            operands.append(("bin", o, operands.pop(), b, c))
        return operands[0]


def compact(program: str, lineno: int, raw: str) -> tuple[str, list[int], list[str]]:
    """The line without comments and blanks, lower case, and each remaining character's 1-based
    column; the comments' texts. Named parameters keep no blanks either (LinuxCNC strips them)."""
    out: list[str] = []
    cols: list[int] = []
    comments: list[str] = []
    i, n = 0, len(raw)
    while i < n:
        c = raw[i]
        if c == "(":
            end = raw.find(")", i)
            if end < 0:
                raise CutsimError(program, lineno, i + 1, "comment '(' without its closing ')'")
            body = raw[i + 1:end]
            if "(" in body:
                raise CutsimError(program, lineno, i + 1 + body.index("(") + 1, "nested comment")
            comments.append(body)
            i = end + 1
            continue
        if c == ";":
            comments.append(raw[i + 1:])
            break
        if c in " \t\r":
            i += 1
            continue
        if c >= "\x80":
            raise CutsimError(program, lineno, i + 1, f"unexpected character '{c}'")
        out.append(c.lower())
        cols.append(i + 1)
        i += 1
    return "".join(out), cols, comments


def parse_line(program: str, lineno: int, raw: str) -> Line | None:
    """One line as a ``Line``; None for a line with nothing to do (blank, comments, ``%``)."""
    r = Reader(program, lineno, raw)
    line = Line(lineno)
    line.messages = [c.strip()[4:].strip() for c in r.comments if c.strip().lower().startswith("msg,")]
    if r.text == "%" or (not r.text and not line.messages):
        return None
    if r.peek() == "/":
        line.delete = True
        r.i += 1
    if r.peek() == "n":
        r.i += 1
        m = re.compile(r"[0-9]+(?:\.[0-9]*)?").match(r.text, r.i)
        if not m:
            raise r.error("N must be followed by a line number", r.i - 1)
        r.i = m.end()
    if r.peek() == "o":
        line.oword = oword(r)
        return line
    while r.i < len(r.text):
        c = r.peek()
        col = r.cols[r.i]
        if c == "#":
            ref = r.parameter_ref()
            r.expect("=", "'=' in the parameter setting")
            line.assigns.append((ref, r.real_value(), col))
        elif c in WORD_LETTERS:
            r.i += 1
            line.words.append((c.upper(), r.real_value(), col))
        elif c == "n":
            raise r.error("the line number N must open the line")
        elif c in "@^":  # polar coordinates (machine.convert_motion, polar.py)
            r.i += 1
            line.words.append((c, r.real_value(), col))
        else:
            raise r.error(f"unexpected character '{c}'")
    return line


def oword(r: Reader) -> tuple:
    """``o<label> keyword [args]...``: the label is a number or ``<name>``."""
    start = r.i
    r.i += 1
    if r.peek() == "<":
        end = r.text.find(">", r.i)
        if end < 0:
            raise r.error("O-word name without its closing '>'", start)
        label = r.text[r.i + 1:end]
        r.i = end + 1
    else:
        m = re.compile(r"[0-9]+").match(r.text, r.i)
        if not m:
            raise r.error("O must be followed by a number or <name>", start)
        label = str(int(m.group()))
        r.i = m.end()
        if r.i == len(r.text):  # "O100" alone: a numbered subprogram (M98 P100 calls it, M99 returns)
            return (label, "program", [], r.cols[start])
    for kw in sorted(OWORD_KEYWORDS, key=len, reverse=True):
        if r.text.startswith(kw, r.i):
            r.i += len(kw)
            break
    else:
        raise r.error("O-word without a known keyword (sub, endsub, call, if, while, do, repeat, ...)")
    args = []
    while r.i < len(r.text):
        if r.peek() != "[":
            raise r.error(f"O-word '{kw}' takes only [expression] arguments")
        args.append(r.real_value())
    return (label, kw, args, r.cols[start])
