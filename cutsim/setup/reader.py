"""Typed, located access to a setup's tables: every error names the setup file, the line and
column of the offending key (or of its table), the table and the key."""
from __future__ import annotations

from cutsim.interp.errors import CutsimError

from .limits import COORD_MAX, MIN_SIZE, is_coord, is_number, show
from .positions import key_positions


class Locator:
    """Where the keys of one setup text are written (the positions are scanned on first use)."""

    def __init__(self, path: str, text: str):
        self.path = path
        self.text = text
        self._positions: dict[tuple, tuple[int, int]] | None = None

    def at(self, path: tuple) -> tuple[int, int]:
        """Line and column of the key or array element at ``path`` (table names, keys and element
        indexes), else of the nearest enclosing one that is written; 1:1 when none is."""
        if self._positions is None:
            self._positions = key_positions(self.text)
        while path:
            if path in self._positions:
                return self._positions[path]
            path = path[:-1]
        return (1, 1)

    def locate(self, table: str, key: str | None, index: int | None) -> tuple[int, int]:
        """Line and column of ``key`` in ``[table]`` (or its ``index``-th ``[[table]]``), however
        it is written (a table header, dotted keys, an inline table, an array of inline tables);
        the table when the key is absent; 1:1 when the table is absent too."""
        path = tuple(table.split(".")) + ((index,) if index is not None else ())
        if key is not None:
            if self._positions is None:
                self._positions = key_positions(self.text)
            if path + (key,) in self._positions:
                return self._positions[path + (key,)]
        return self.at(path)


class Reader:
    """Typed access to one TOML table that remembers which keys were read."""

    def __init__(self, loader: "Locator", table: dict, where: str, index: int | None = None):
        self.loader, self.table, self.where, self.index = loader, table, where, index
        self.used: set[str] = set()

    def fail(self, key: str | None, message: str) -> CutsimError:
        line, col = self.loader.locate(self.where, key, self.index)
        head = f"[{self.where}]" if self.index is None else f"[[{self.where}]] #{self.index + 1}"
        return CutsimError(self.loader.path, line, col, f"{head} {key + ': ' if key else ''}{message}")

    def get(self, key: str, kind, default=..., check=None, why: str = ""):
        self.used.add(key)
        if key not in self.table:
            if default is ...:
                raise self.fail(key, "is required")
            return default
        v = self.table[key]
        if kind is float:
            ok = is_number(v)
            v = float(v) if ok else v
        elif kind is int:
            ok = isinstance(v, int) and not isinstance(v, bool)
        else:
            ok = isinstance(v, kind)
        if not ok:
            tname = {float: "a number", int: "a whole number", bool: "true or false", str: "a string",
                     list: "a list", dict: "a table"}[kind]
            raise self.fail(key, f"must be {tname}, not {show(v)}")
        if check is not None and not check(v):
            raise self.fail(key, f"{why} (got {show(v)})")
        return v

    def pair(self, key: str, default=..., increasing: bool = True):
        v = self.get(key, list, default)
        if v is default:
            return v
        if len(v) != 2 or not all(is_number(c) for c in v):
            raise self.fail(key, f"must be two finite numbers [low, high], not {show(v)}")
        if not all(is_coord(c) for c in v):
            raise self.fail(key, f"must lie within -{COORD_MAX:g} to {COORD_MAX:g} mm, not {show(v)}")
        if increasing and not v[0] < v[1]:
            raise self.fail(key, f"must be [low, high] with low < high, not {show(v)}")
        return (float(v[0]), float(v[1]))

    def points(self, key: str, minimum: int = 3, maximum: int = 100_000):
        v = self.get(key, list)
        if not minimum <= len(v) <= maximum or not all(isinstance(p, list) and len(p) == 2 and
                                                       all(is_number(c) for c in p) for p in v):
            raise self.fail(key, f"must be a list of {minimum} to {maximum} [a, b] pairs of finite numbers")
        if not all(is_coord(c) for p in v for c in p):
            raise self.fail(key, f"coordinates must lie within -{COORD_MAX:g} to {COORD_MAX:g} mm")
        return tuple((float(p[0]), float(p[1])) for p in v)

    def size(self, key: str, lo: float, hi: float) -> None:
        """A stock size from ``lo`` to ``hi`` must be at least MIN_SIZE."""
        if hi - lo < MIN_SIZE:
            raise self.fail(key, f"the stock must be at least {MIN_SIZE:g} mm thick (got {hi - lo:g})")

    def fail_at(self, key: str, sub: tuple, message: str) -> CutsimError:
        """An error about a part of ``key``'s value (``sub``: element indexes / inner keys), at that part."""
        path = tuple(self.where.split(".")) + ((self.index,) if self.index is not None else ()) + (key,) + sub
        return CutsimError(self.loader.path, *self.loader.at(path), f"[{self.where}] {key}: {message}")

    def done(self) -> None:
        for key in self.table:
            if key not in self.used:
                raise self.fail(key, "unknown key")

