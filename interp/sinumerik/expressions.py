"""The Sinumerik reader's first layer: the characters of one block (words, numbers, names) and its
expressions, by precedence (OR ... B_AND, comparisons, <<, + -, * / DIV MOD, unary, primary).
"""
from __future__ import annotations

from ..errors import CutsimError
from .syntax import (ADDRESSES, BinOp, EXP_RE, Expr, FuncCall, FUNCS, Index, KEYWORDS, MAX_DIGITS, MAX_NESTING,
    NAME_RE, Neg, Not, Num, NUMBER_RE, RIndex, SIGNED_RE, Str, SYS_RE, Var)


# ---------------------------------------------------------------------------------------------
# reading: characters -> expressions and statements
# Binary operators from the lowest priority to the highest (Job Planning, "Priority of the
# operations"): comparisons, <<, OR, XOR, AND, B_OR, B_XOR, B_AND, + -, * / DIV MOD.
COMPARISONS = ("==", "<>", "<=", ">=", "<", ">")
WORD_LEVELS = (("OR",), ("XOR",), ("AND",), ("B_OR",), ("B_XOR",), ("B_AND",))


class ExprScanner:
    """Character scanner for one line (comment removed)."""

    def __init__(self, prog: str, line: int, text: str):
        self.prog, self.line, self.s, self.i = prog, line, text, 0
        self.depth = 0  # expressions, parentheses and signs open (MAX_NESTING)

    def enter(self, col: int) -> None:
        self.depth += 1
        if self.depth > MAX_NESTING:
            raise self.err(col, f"expression nested deeper than {MAX_NESTING} levels (parentheses, functions, signs)")

    def err(self, col: int, msg: str) -> CutsimError:
        return CutsimError(self.prog, self.line, col, msg)

    def ws(self) -> None:
        while self.i < len(self.s) and self.s[self.i] in " \t\f\v":
            self.i += 1

    def peek(self) -> str:
        self.ws()
        return self.s[self.i] if self.i < len(self.s) else ""

    def ident(self) -> str:
        m = NAME_RE.match(self.s, self.i)
        if not m:
            return ""
        self.i = m.end()
        return m.group(0).upper()

    def peek_word(self) -> str:
        """The name at the cursor (upper case) without consuming it."""
        self.ws()
        m = NAME_RE.match(self.s, self.i)
        return m.group(0).upper() if m else ""

    def take_word(self, word: str) -> bool:
        if self.peek_word() == word:
            self.i += len(word)
            return True
        return False

    def at_end(self) -> bool:
        return not self.peek()

    def close(self, ch: str) -> None:
        if self.peek() != ch:
            raise self.err(self.i + 1, f"'{ch}' expected")
        self.i += 1

    def digits(self, col: int, raw: str) -> None:
        """A written number has at most MAX_DIGITS digits (a 309-digit number is no number)."""
        if len(raw) <= MAX_DIGITS:
            return
        n = sum(ch in "0123456789" for ch in raw)
        if n > MAX_DIGITS:
            shown = raw if len(raw) <= 24 else f"{raw[:12]}...{raw[-6:]}"
            raise self.err(col, f"the number {shown} has {n} digits, more than the {MAX_DIGITS} a number may have")

    def number_word(self) -> float | None:
        """After an address letter: a plain number (G1, X-10.5)."""
        m = SIGNED_RE.match(self.s, self.i)
        if not m:
            return None
        self.digits(self.i + 1, m.group(0))
        j = m.end()
        if j < len(self.s) and (self.s[j] == "." or self.s[j] in "0123456789"):
            raise self.err(self.i + 1, f"malformed number '{self.s[self.i:j + 1]}'")
        self.i = j
        return float(m.group(0).replace("\u2212", "-"))

    # expressions, by priority (COMPARISONS lowest, then <<, WORD_LEVELS, + -, * / DIV MOD, unary)
    def expr(self) -> Expr:
        self.enter(self.i + 1)
        left = self.concat()
        while True:
            self.ws()
            op = next((o for o in COMPARISONS if self.s.startswith(o, self.i)), None)
            if op is None or self.s.startswith("<<", self.i):
                break
            opcol = self.i + 1
            self.i += len(op)
            left = BinOp(op, left, self.concat(), opcol)
        self.depth -= 1
        return left

    def concat(self) -> Expr:
        left = self.words(0)
        while self.peek() == "<" and self.s.startswith("<<", self.i):
            opcol = self.i + 1
            self.i += 2
            left = BinOp("<<", left, self.words(0), opcol)
        return left

    def words(self, level: int) -> Expr:
        """OR, XOR, AND, B_OR, B_XOR, B_AND (level 0 .. 5), then the additive operators."""
        if level == len(WORD_LEVELS):
            return self.additive()
        left = self.words(level + 1)
        while self.peek_word() in WORD_LEVELS[level]:
            op = self.peek_word()
            opcol = self.i + 1
            self.i += len(op)
            left = BinOp(op, left, self.words(level + 1), opcol)
        return left

    def additive(self) -> Expr:
        left = self.term()
        while self.peek() in ("+", "-"):
            op = self.s[self.i]
            self.i += 1
            opcol = self.i  # the operator's 1-based column
            left = BinOp(op, left, self.term(), opcol)
        return left

    def term(self) -> Expr:
        left = self.unary()
        while True:
            c = self.peek()
            if c in ("*", "/"):
                op = c
            elif self.peek_word() in ("DIV", "MOD"):
                op = self.peek_word()
            else:
                return left
            opcol = self.i + 1
            self.i += len(op)
            left = BinOp(op, left, self.unary(), opcol)

    def unary(self) -> Expr:
        c = self.peek()
        col = self.i + 1
        w = self.peek_word()
        if c in ("-", "+", "\u2212") and c or w in ("NOT", "B_NOT"):
            self.enter(col)
            self.i += len(w) if w in ("NOT", "B_NOT") else 1
            v = self.unary()
            self.depth -= 1
            if w in ("NOT", "B_NOT"):
                return Not(v, col, w == "B_NOT")
            return Neg(v) if c != "+" else v
        return self.primary()

    def primary(self) -> Expr:
        c = self.peek()
        col = self.i + 1
        if not c:
            raise self.err(col, "expression expected at the end of the line")
        m = NUMBER_RE.match(self.s, self.i)
        if m:
            return self.number(col, m)
        if c == "(":
            self.i += 1
            v = self.expr()
            self.close(")")
            return v
        if c in "\"'":
            j = self.s.find(c, self.i + 1)
            if j < 0:
                raise self.err(col, "unterminated string")
            v = Str(self.s[self.i + 1:j])
            self.i = j + 1
            return v
        if c == "$":
            m = SYS_RE.match(self.s, self.i)
            if not m:
                raise self.err(col, "a system variable name is expected after '$'")
            self.i = m.end()
            return self.indexed(m.group(0).upper(), col)
        if c.isalpha() or c == "_":
            return self.name_expr(col)
        raise self.err(col, f"unexpected character '{c}' in an expression")

    def number(self, col: int, m) -> Num:
        self.digits(col, m.group(0))
        self.i = m.end()
        value = float(m.group(0))
        e = EXP_RE.match(self.s, self.i)
        if e:
            self.i = e.end()
            exp = int(e.group(0)[2:])
            if abs(exp) > 300:
                raise self.err(col, f"the exponent EX{exp} is out of range")
            value *= 10.0 ** exp
        elif self.i < len(self.s) and (self.s[self.i] == "." or self.s[self.i].isalpha()
                                       and self.s[self.i].upper() not in ADDRESSES | {"R", "C", "A", "N"}
                                       and self.peek_word() not in KEYWORDS):
            raise self.err(col, f"malformed number '{self.s[col - 1:self.i + 1]}'")
        return Num(value)

    def indexed(self, name: str, col: int) -> Expr:
        """NAME or NAME[i, j] (array element, system variable with its index)."""
        if self.peek() != "[":
            return Var(name, col)
        self.i += 1
        idx = [self.expr()]
        while self.peek() == ",":
            self.i += 1
            idx.append(self.expr())
        self.close("]")
        return Index(name, tuple(idx), col)

    def name_expr(self, col: int) -> Expr:
        """A function call, R[expr], an array element or a variable."""
        name = self.ident()
        if name in FUNCS:
            if self.peek() != "(":
                raise self.err(self.i + 1, f"{name} needs its argument in parentheses")
            self.i += 1
            args = [self.expr()]
            while self.peek() == ",":
                self.i += 1
                args.append(self.expr())
            self.close(")")
            if len(args) != FUNCS[name]:
                raise self.err(col, f"{name} takes {FUNCS[name]} argument(s)")
            return FuncCall(name, tuple(args), col)
        if self.peek() == "[" and name == "R":  # R[expr]
            self.i += 1
            idx = self.expr()
            self.close("]")
            return RIndex(idx, col)
        if name in ("AC", "IC") and self.peek() == "(":
            raise self.err(col, f"{name}(..) only goes with an address: X={name}(..)")
        return self.indexed(name, col)
