"""Where each key of a TOML text is written: errors of the setup and of batch manifests name the
line and column of the offending key, which tomllib does not tell."""
from __future__ import annotations

import bisect
import re
import tomllib

_BARE_KEY = re.compile(r"[A-Za-z0-9_\-]+")
_SCALAR = re.compile(r"[^,\]\}\r\n#]*")


def key_positions(text: str) -> dict[tuple, tuple[int, int]]:
    """(line, column) of every key of a TOML text that tomllib accepted, by its full path: table
    names and keys as strings, the n-th ``[[table]]`` or array element as the integer n. Header
    tables map to their header line; dotted keys and inline tables to the key itself; array
    elements to the element's first character. Never raises: a position is a courtesy, and a text
    the scanner cannot follow gives no positions (errors then name line 1)."""
    try:
        return _Scanner(text).run()
    except Exception:  # noqa: BLE001 - never fail the error report
        return {}


class _Scanner:
    """One pass over the text, recording positions in ``pos``."""

    def __init__(self, text: str):
        self.text, self.n = text, len(text)
        self.starts = [0] + [m.end() for m in re.finditer("\n", text)]
        self.pos: dict[tuple, tuple[int, int]] = {}

    def lc(self, i: int) -> tuple[int, int]:
        row = bisect.bisect_right(self.starts, i) - 1
        return row + 1, i - self.starts[row] + 1

    def ws(self, i: int, newlines: bool = False) -> int:
        text, n = self.text, self.n
        while i < n:
            c = text[i]
            if c in " \t\r" or newlines and c == "\n":
                i += 1
            elif newlines and c == "#":
                while i < n and text[i] != "\n":
                    i += 1
            else:
                break
        return i

    def string_end(self, i: int) -> int:
        text, n = self.text, self.n
        q = text[i]
        if text.startswith(q * 3, i):
            j = text.find(q * 3, i + 3)
            if j < 0:
                return n
            while j + 3 < n and text[j + 3] == q:  # up to two quotes just before the closing ones
                j += 1
            return j + 3
        j = i + 1
        while j < n and text[j] != q and text[j] != "\n":
            j += 2 if q == '"' and text[j] == "\\" else 1
        return j + 1

    def key(self, i: int):
        """(the parts of a dotted key, where each starts, the index after it)."""
        text, n = self.text, self.n
        parts, at = [], []
        while i < n:
            i = self.ws(i)
            at.append(i)
            if i < n and text[i] in "\"'":
                j = self.string_end(i)
                parts.append(tomllib.loads("k = " + text[i:j])["k"])
                i = j
            else:
                m = _BARE_KEY.match(text, i)
                if not m:
                    break
                parts.append(m.group())
                i = m.end()
            i = self.ws(i)
            if i < n and text[i] == ".":
                i += 1
                continue
            break
        return parts, at, i

    def value(self, i: int, path: tuple) -> int:
        text, n = self.text, self.n
        c = text[i] if i < n else ""
        if c in ("\"", "'"):
            return self.string_end(i)
        if c in ("[", "{"):
            close, k = ("]" if c == "[" else "}"), 0
            i += 1
            while True:
                i = self.ws(i, True)
                if i >= n or text[i] == close:
                    return i + 1
                if c == "[":
                    self.pos.setdefault(path + (k,), self.lc(i))
                    i = self.value(i, path + (k,))
                    k += 1
                else:
                    i = self.keyval(i, path)
                i = self.ws(i, True)
                if i < n and text[i] == ",":
                    i += 1
                elif i < n and text[i] != close:
                    return i  # not TOML after all: give up on this value
        return _SCALAR.match(text, i).end()

    def keyval(self, i: int, path: tuple) -> int:
        parts, at, i = self.key(i)
        if not parts:
            return i + 1
        for d in range(len(parts)):
            self.pos.setdefault(path + tuple(parts[:d + 1]), self.lc(at[d]))
        i = self.ws(i)
        if i < self.n and self.text[i] == "=":
            i = self.ws(i + 1)
        return self.value(i, path + tuple(parts))

    def header(self, i: int, arrays: dict, headers: set) -> tuple[tuple, int]:
        """A ``[table]`` or ``[[table]]`` header at ``i``: (the table's full path, the index after it)."""
        text, start = self.text, i
        double = text.startswith("[[", i)
        parts, _at, i = self.key(i + (2 if double else 1))
        full: tuple = ()
        for d, p in enumerate(parts):
            full += (p,)
            if d < len(parts) - 1 and full in arrays:
                full += (arrays[full],)
        if double:
            arrays[full] = arrays.get(full, -1) + 1
            self.pos.setdefault(full, self.lc(start))
            full += (arrays[full],)
        if full not in headers:  # an explicit header names the table (not an earlier sub-table)
            headers.add(full)
            self.pos[full] = self.lc(start)
        for d in range(1, len(full)):
            self.pos.setdefault(full[:d], self.lc(start))
        i = text.find("]", i)
        return full, (i + (2 if double else 1) if i >= 0 else self.n)

    def run(self) -> dict[tuple, tuple[int, int]]:
        text, n = self.text, self.n
        table: tuple = ()
        arrays: dict[tuple, int] = {}  # [[name]] -> index of its last element
        headers: set[tuple] = set()
        i = 0
        while True:
            i = self.ws(i, True)
            if i >= n:
                break
            if text[i] == "[":
                table, i = self.header(i, arrays, headers)
            else:
                i = self.keyval(i, table)
            while i < n and text[i] != "\n":  # the rest of the line: spaces and a comment
                if text[i] == "#":
                    i = text.find("\n", i)
                    i = n if i < 0 else i
                    break
                i += 1
        return self.pos
