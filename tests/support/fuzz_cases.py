"""Grammar-aware fuzzing of cutsim: deterministic case generators, a robust runner, classification.

Used by ``tests/app/test_fuzz.py`` (a short fixed-seed run) and ``bench/fuzz.py`` (long runs).

A *case* is a set of files (program, setup, extra files such as Sinumerik ``NAME.spf`` or a mesh
stock) and a command line (``cutsim simulate prog.nc --setup setup.toml --out out ...``), run in
its own directory. ``make_case(seed, index)`` builds case ``index`` of run ``seed`` the same way
every time (for a fixed tree of examples): mutations of the shipped examples, grammar-generated
programs per dialect, setup mutations and command-line mutations.

The runner keeps persistent worker processes (forked after cutsim is imported) that call the CLI
in-process (``cutsim.cli.main.main(args, standalone_mode=True)``), with a wall-clock timeout per
case (the worker dumps its stack with faulthandler and is killed and replaced), a memory cap
(``RLIMIT_AS``) and stdout/stderr captured at the file-descriptor level. Each result is put in one
class (``CLASSES``); ``FAILURES`` are the classes that break cutsim's contract.
"""
from __future__ import annotations

import faulthandler
import math
import os
import random
import re
import resource
import shlex
import shutil
import signal
import sys
import time
import tomllib
import traceback
from dataclasses import dataclass, field
from pathlib import Path

from cutsim.batch.process import cpu_seconds, set_limits

ROOT = Path(__file__).resolve().parents[2]
SHARED = Path(os.environ.get("CUTSIM_SHARED", ROOT.parent / "shared"))

# -------------------------------------------------------------------------------------------------
# classes

CLASSES = ("ok-exit0", "ok-exit2", "exit1", "usage", "exit3", "traceback", "hang", "memory", "segfault",
           "leaky-part", "missing-part", "bad-location", "wrong-line", "partial-output", "other-exit")
# the classes that break the contract (zero expected)
FAILURES = ("exit3", "traceback", "hang", "memory", "segfault", "leaky-part", "missing-part", "bad-location",
            "wrong-line", "partial-output", "other-exit")


@dataclass
class Case:
    index: int
    kind: str                      # "example", "grammar", "setup", "cli"
    dialect: str
    files: dict[str, bytes]        # file name (relative to the case directory) -> contents
    argv: list[str]                # the arguments after "cutsim"
    notes: list[str] = field(default_factory=list)
    out: str | None = "out"        # the --out directory (relative), when the case has one
    fmt: str = "stl"
    expect_line: tuple[str, int] | None = None  # (file, line) a sole injected error must be reported at
    missing: tuple[str, ...] = ()  # files the command names on purpose that do not exist

    @property
    def program(self) -> str | None:
        return next((a for a in self.argv[1:] if not a.startswith("-") and a in self.files), None)

    def command(self) -> str:
        return "cutsim " + " ".join(shlex.quote(a) for a in self.argv)

    def size(self) -> int:
        return sum(len(v) for v in self.files.values()) + len(" ".join(self.argv))


# -------------------------------------------------------------------------------------------------
# corpus: the shipped examples (and the tests' programs) with their setups


@dataclass
class Seed:
    label: str
    dialect: str
    kind: str
    program_name: str
    program: bytes
    setup: bytes
    extra: dict[str, bytes]
    valid: bool = False  # a shipped example: simulates without errors




_CORPUS: dict[tuple, list[Seed]] = {}
PROGRAM_EXT = (".nc", ".mpf", ".NC", ".MPF")


def corpus_roots() -> list[Path]:
    programs = ROOT / "tests" / "data" / "programs"
    return [ROOT / "examples", SHARED / "examples", programs / "isg", programs / "mill", programs / "checks",
            ROOT / "tests" / "data" / "bad" / "cnc8x6", ROOT / "tests" / "data" / "bad" / "isg" / "lathe"]


def _seed(prog: Path, toml: Path, label: str) -> Seed | None:
    try:
        setup = toml.read_bytes()
        data = tomllib.loads(setup.decode("utf-8"))
        m = data["machine"]
        dialect, kind = m["dialect"], m["kind"]
    except Exception:  # noqa: BLE001 - a broken file in the corpus is skipped
        return None
    extra = {}
    for p in sorted(prog.parent.iterdir()):
        if p.suffix.lower() == ".spf":
            extra[p.name] = p.read_bytes()
    # files the setup names (mesh stock, design checks), by a simple relative path
    for key in re.findall(rb'path\s*=\s*"([^"/\\]+)"', setup):
        q = toml.parent / key.decode("utf-8", "replace")
        if q.is_file() and q.stat().st_size < 20_000_000:
            extra[q.name] = q.read_bytes()
    valid = prog.parent.parent.name == "examples" and toml.parent == prog.parent
    return Seed(label, dialect, kind, prog.name, prog.read_bytes(), setup, extra, valid)


def corpus(roots: list[Path] | None = None) -> list[Seed]:
    """Program + setup pairs under the roots (globbed now: examples may be added while we run)."""
    roots = corpus_roots() if roots is None else roots
    key = tuple(str(r) for r in roots)
    if key in _CORPUS:
        return _CORPUS[key]
    seeds: list[Seed] = []
    seen: set[Path] = set()
    for root in roots:
        if not root.is_dir():
            continue
        for prog in sorted(root.rglob("*")):
            if prog.suffix not in PROGRAM_EXT or not prog.is_file() or prog.resolve() in seen:
                continue
            seen.add(prog.resolve())
            same = prog.with_suffix(".toml")
            tomls = [same] if same.is_file() else sorted(prog.parent.glob("*.toml"))
            related = [t for t in tomls if prog.stem.split("-")[0] == t.stem.split("-")[0].split(".")[0]]
            tomls = related or tomls
            for t in tomls:
                s = _seed(prog, t, f"{prog.relative_to(root.parent)}+{t.name}")
                if s is not None:
                    seeds.append(s)
    # the ISG examples once more on the tests' short bar (the full 100 mm threads take seconds)
    short = ROOT / "tests" / "data" / "programs" / "isg" / "short.toml"
    for root in roots:
        for prog in sorted((root / "isg-lathe").glob("*.nc")) if (root / "isg-lathe").is_dir() else []:
            s = _seed(prog, short, f"{prog.relative_to(root.parent)}+short.toml") if short.is_file() else None
            if s is not None:
                seeds.append(s)
    _CORPUS[key] = seeds
    return seeds


# -------------------------------------------------------------------------------------------------
# small helpers

def _r(rng: random.Random, lo: float, hi: float, nd: int = 3) -> float:
    return round(rng.uniform(lo, hi), nd)


def fmt_num(v: float, nd: int = 3, point: bool = False) -> str:
    s = f"{v:.{nd}f}".rstrip("0")
    if s.endswith("."):
        return s if point else s[:-1]
    if s in ("-0", "-0."):
        s = "0"
    return s


WEIRD_NUMBERS = [
    "0", "-0", "0.", ".0", ".", "-", "+", "-.", "1e5", "1E-5", "1e308", "1e999", "-1e999", "inf", "-inf", "nan",
    "NaN", "INF", "Infinity", "1" + "0" * 40, "9" * 400, "0." + "0" * 400 + "1", "1." + "9" * 300,
    "3.14159265358979323846264338327950288419716939937510", "-999999999", "999999999999", "0.0000001",
    "1_000", "0x10", "1,5", "--5", "+-5", "5-", "5..5", "1.2.3", "\u22125", "\u2212.5",
    "\u0661\u0662\u0663", "\uff11\uff12", "\u00b2", "\u09e9", "\u0e53", "\U0001d7d9", "\u2160",
    "99.99", "99.991", "100", "360", "360.0001", "-0.0001", "4294967296", "18446744073709551617",
    "2147483648", "-2147483649", "1e-300", "5e", "e5", "1e+", "NaN(0x1)",
    "99999.9999", "-99999.9999", "100000", "99999999", "100000000", "0.001", "0.0001", "359.999", "99.99",
]


def weird_number(rng: random.Random) -> str:
    if rng.random() < 0.7:
        return rng.choice(WEIRD_NUMBERS)
    k = rng.choice([1, 2, 5, 20, 60, 200])
    s = "".join(rng.choice("0123456789") for _ in range(k))
    if rng.random() < 0.5:
        i = rng.randrange(len(s) + 1)
        s = s[:i] + "." + s[i:]
    return rng.choice(["", "-", "+"]) + s


# -------------------------------------------------------------------------------------------------
# dialect vocabularies (tokens for insertion; valid and invalid)

def _tok_cnc8x6(rng: random.Random) -> str:
    c = rng.random()
    if c < 0.25:
        return "G" + rng.choice(["00", "01", "02", "03", "33", "90", "91", "94", "95", "17", "18", "19", "09", "10",
                                 "98", "73", "0", "1", "04", "4", "330", "-1", "1.5", "", "99", "00G01"])
    if c < 0.35:
        return "M" + rng.choice(["03", "04", "05", "02", "30", "00", "01", "08", "09", "41", "44", "45", "06", "3", "",
                                 "99", "17", "29"])
    if c < 0.75:
        a = rng.choice("XYZIJKEFRSTDLQ&N")
        v = rng.choice([fmt_num(_r(rng, -100, 100)), fmt_num(_r(rng, -5, 5), point=True) + ".", weird_number(rng),
                        "R" + str(rng.randint(0, 99)).zfill(2), str(rng.randint(0, 400))])
        return a + v
    return rng.choice([
        "R15=-00120.000", "R10=250.0", "R00=1", "R80=2", "R04=120.0", "R16= \u221200120.000", "R99=1e5", "R1=",
        "=5", "G73 L10 Q3", "G73 L5 Q99999999", "G73 L1 Q0", "G73 LR10 QR11", "G73", "Q5", "&1100", "D9",
        "T9", "S1000", "Z1.05 G10", "G09 G02 X0 Y0 I10", "G98", "\"comment", "\u201ccomment", "\u201eA",
        "\u00cdB", "\u0148C", "E12", "E12.", "J12", "I-1", "I400", "F0", "F100", "FR10", "X", "Z", "N", "G33 F1.5",
        "G33 Z-5 F1.5 J2 E3.", "%", ";x", "(x)", "#1", "$", "X1X2", "G00 G01",
    ])


def _tok_isg(rng: random.Random) -> str:
    c = rng.random()
    if c < 0.25:
        return "G" + rng.choice(["00", "01", "02", "03", "33", "51", "52", "90", "91", "94", "95", "17", "18", "19",
                                 "0", "1", "04", "10", "99", "", "-1"])
    if c < 0.35:
        return "M" + rng.choice(["03", "04", "05", "30", "02", "29", "17", "06", "00", "09", "3", "99", ""])
    if c < 0.65:
        a = rng.choice(["X", "Y", "Z", "I", "J", "K", "F", "S", "T", "D", "N"])
        return a + rng.choice([fmt_num(_r(rng, -100, 100)), weird_number(rng), str(rng.randint(0, 500))])
    return rng.choice([
        "S.OFFSET=90", "S.OFFSET=180", "S.OFFSET 120", "S.OFFSET=-10", "S.OFFSET=360", "S.OFFSET=", "S.SPEED=10",
        "S.OFFSET=1e400", "LL Laengsgewinde", "LL L\u00e4ngsgewinde", "LL SUB", "LL", "LL sub", "L name", "%L SUB",
        "%MAIN", "%", "M29", "M17", "(comment", "(a(b)c)", ";comment", ")", "#COMMENT BEGIN", "#COMMENT END",
        "#VAR", "#ENDVAR", "#CHANNEL INIT[CONFIG]", "#TRAFO ON", "$IF V.A.ACS.X > 0", "$ENDIF", "$ELSE",
        "$FOR P1 = 0, 10, 1", "$ENDFOR", "$GOTO [N10]", "V.L.X=1", "P1=5", "[X1+2]", "X[1+2]", "K1.5", "K0",
        "K-1", "I1.5", "T0", "D0", "N10", "G33 Z10 K1.5",
    ])


CYCLE_NAMES = ["SLOT1", "SLOT2", "POCKET1", "POCKET2", "POCKET3", "POCKET4", "CYCLE71", "CYCLE72"]
CYCLE_ARITY = {"SLOT1": 24, "SLOT2": 23, "POCKET1": 20, "POCKET2": 17, "POCKET3": 23, "POCKET4": 19,
               "CYCLE71": 16, "CYCLE72": 17}


def _rand_param(rng: random.Random) -> str:
    c = rng.random()
    if c < 0.15:
        return ""
    if c < 0.65:
        return fmt_num(_r(rng, -50, 100, rng.choice([0, 1, 3])))
    if c < 0.8:
        return weird_number(rng)
    return rng.choice(['"KONTUR"', '"A:B"', '""', "R1", "R1*2", "SQRT(-1)", "1/0", "AA", '"x', "(1", "-", "TRUE",
                       "1E3", "R[1]", "POT(1e200)", "ACOS(2)", "ATAN2(0,0)", "ROUND(1.5)", "TRUNC(-1.5)",
                       "MINVAL(1)", "MAXVAL(1,2,3)", "10000000000"])


def random_cycle_call(rng: random.Random) -> str:
    name = rng.choice(CYCLE_NAMES + ["CYCLE81", "CYCLE832", "MSG", "WORKPIECE", "POCKET5", "SLOT"])
    n = CYCLE_ARITY.get(name, 5)
    k = rng.choice([0, 1, rng.randint(0, n), n, n, n + 1, n + 5])
    return f"{name}({', '.join(_rand_param(rng) for _ in range(k))})"


def _tok_sinumerik(rng: random.Random) -> str:
    c = rng.random()
    if c < 0.2:
        return "G" + rng.choice(["0", "1", "2", "3", "17", "18", "19", "90", "91", "94", "95", "40", "41", "42", "54",
                                 "500", "64", "9", "4", "33", "331", "", "00", "-1"])
    if c < 0.3:
        return "M" + rng.choice(["3", "4", "5", "6", "30", "2", "17", "0", "8", "99", "", "03"])
    if c < 0.55:
        a = rng.choice(["X", "Y", "Z", "I", "J", "K", "F", "S", "T", "D", "L", "P", "CR=", "X=", "Z=", "I=", "F="])
        return a + rng.choice([fmt_num(_r(rng, -100, 100)), weird_number(rng), "AC(5)", "IC(-2)", "R1", "R[2]",
                               "SQRT(R1)", "AC()", "AC(", "(1+2)*3", "R1/0", "SIN(30)+COS(60)", "POT(1e300)"])
    if c < 0.7:
        return random_cycle_call(rng)
    return rng.choice([
        "DEF REAL AA=1, BB", "DEF INT CNT=0", "DEF BOOL FLAG", "DEF STRING[10] S1", "DEF REAL A", "DEF", "DEF FRAME F1",
        "R1=R1+1", "R1=5 R2=R1*2", "R[5]=2", "R[R1]=3", "R-1=2", "R99999=1", "R1=1/0", "R1=SQRT(-1)", "R1=ACOS(2)",
        "IF R1<5 GOTOB LBL", "IF R1==1 GOTOF END", "IF GOTOF END", "GOTOF END", "GOTOB LBL", "GOTO LBL", "GOTOF N10",
        "GOTOB N10", "REPEAT LBL P=3", "REPEAT LBL END P=2", "REPEAT", "LBL:", "END:", "AB:", "A:", "PROC SUB", "RET",
        "SUB", "SUB P3", "SUB P999999", "L10", "M17", "ENDIF", "WHILE R1<3", "ENDWHILE", "FOR R1=1 TO 3", "CASE",
        'MSG("x")', 'MSG("a;b")', "STOPRE", "SUPA", "DIAMOF", "TRAFOOF", "G41 D1", "D0", "T2 D1 M6", "T99 M6",
        "X=AC(5)", "X=IC(-2)", "CR=5", "CR=-5", "I=AC(3) J=AC(4)", "%_N_SUB_SPF", ";#7__DlgK contour definition begin",
        ";#End contour definition end", "G1X10Y20", "N10", "N", "X10X20", "G0 G1", '"', "(", ")", "[", "]", "$A",
        "G1 X5 RND=2", "G1 Y5 CHF=1", "G1 X0 CHR=1", "RNDM=1", "RNDM=0", "FRC=50", "FRCM=20", "RND=-1", "CHF=1e9",
        'EXTCALL "SUB"', "PCALL SUB", "PCALL /_N_WKS_DIR/_N_SUB_SPF(1)", 'CALL "L_VENDOR"', "L_VENDOR", "CYCLE_ABC(1,2)",
    ])


VOCAB = {"cnc8x6": _tok_cnc8x6, "isg": _tok_isg, "sinumerik": _tok_sinumerik}
BAD_TOKENS = ["G77", "M77", "G4711", "M4711"]  # errors in every dialect: the injected-error oracle


# -------------------------------------------------------------------------------------------------
# program mutations

_NUM_RE = re.compile(r"\d+\.?\d*|\.\d+")


def _split(text: str) -> list[str]:
    return text.replace("\r\n", "\n").replace("\r", "\n").split("\n")


def mutate_lines(rng: random.Random, lines: list[str], tok, grammar_line=None) -> list[str]:
    """One structural or lexical mutation of a program (or setup) given as lines; returns a note."""
    ops = ["delete", "duplicate", "swap", "move", "number", "number", "number-mild", "number-mild", "number-mild",
           "number-mild", "letter", "insert-token",
           "insert-token", "insert-line", "truncate", "lower", "strip-comment", "dup-many", "split-line",
           "join-lines", "remove-char"]
    op = rng.choice(ops)
    n = len(lines)
    i = rng.randrange(n) if n else 0
    if not lines:
        lines.append(tok(rng))
        return "empty->token"
    if op == "delete":
        del lines[i]
    elif op == "duplicate":
        lines.insert(i, lines[i])
    elif op == "dup-many":
        k = rng.choice([10, 50, 300])
        lines[i:i + 1] = [lines[i]] * k
        op = f"dup-many x{k}"
    elif op == "swap":
        j = rng.randrange(n)
        lines[i], lines[j] = lines[j], lines[i]
    elif op == "move":
        ln = lines.pop(i)
        lines.insert(rng.randrange(len(lines) + 1), ln)
    elif op == "number":
        ms = list(_NUM_RE.finditer(lines[i]))
        if ms:
            m = rng.choice(ms)
            lines[i] = lines[i][:m.start()] + weird_number(rng) + lines[i][m.end():]
        else:
            lines[i] = lines[i] + " " + tok(rng)
    elif op == "number-mild":
        ms = list(_NUM_RE.finditer(lines[i]))
        if ms:
            m = rng.choice(ms)
            v = float(m.group()) if m.group() != "." else 0.0
            v = v if math.isfinite(v) and abs(v) < 1e12 else 1.0
            nv = rng.choice([v * rng.uniform(0.5, 1.5), v + rng.uniform(-2, 2), v * 2, v / 2, round(v), v + 0.001])
            txt = fmt_num(abs(nv), 3, point=True)
            if "." in m.group() and "." not in txt:
                txt += "."
            lines[i] = lines[i][:m.start()] + txt + lines[i][m.end():]
    elif op == "letter":
        ms = [k for k, ch in enumerate(lines[i]) if ch.isalpha()]
        if ms:
            k = rng.choice(ms)
            ch = rng.choice("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz\u00e4\u00df\u0131\u0130\u017f\u212a")
            lines[i] = lines[i][:k] + ch + lines[i][k + 1:]
    elif op == "insert-token":
        ws = [m.start() for m in re.finditer(r"\s|$", lines[i])] or [len(lines[i])]
        k = rng.choice(ws)
        lines[i] = lines[i][:k] + " " + tok(rng) + lines[i][k:]
    elif op == "insert-line":
        ln = grammar_line(rng) if grammar_line is not None and rng.random() < 0.5 else \
            " ".join(tok(rng) for _ in range(rng.randint(1, 4)))
        lines.insert(i, ln)
    elif op == "truncate":
        k = rng.randrange(len(lines[i]) + 1)
        lines[i] = lines[i][:k]
        del lines[i + 1:]
    elif op == "lower":
        lines[i] = lines[i].lower() if rng.random() < 0.7 else lines[i].upper()
    elif op == "strip-comment":
        lines[i] = re.sub(r"[;\"\u201c(].*", "", lines[i]) if rng.random() < 0.5 else ";" + lines[i]
    elif op == "split-line":
        k = rng.randrange(len(lines[i]) + 1)
        lines[i:i + 1] = [lines[i][:k], lines[i][k:]]
    elif op == "join-lines":
        if i + 1 < n:
            lines[i:i + 2] = [lines[i] + " " + lines[i + 1]]
    elif op == "remove-char":
        if lines[i]:
            k = rng.randrange(len(lines[i]))
            lines[i] = lines[i][:k] + lines[i][k + 1:]
    return op


BYTE_INSERTS = [b"\x00", b"\x1a", b"\xff", b"\xfe\xff", b"\xef\xbb\xbf", b"\r", b"\r\n", b"\t", b"\x0c", b"\x0b",
                b"\xc2\x85", b"\xe2\x80\xa8", b"\xe2\x80\xa9", b"\x1c", b"\x1e", b"\xc3", b"\xe9", b"\x80",
                b"\xed\xa0\x80", b"\xf4\x90\x80\x80", b"\xe2\x80\x8b", b"\xcc\x88", b"\xf0\x9f\x92\xa9", b"\\",
                b"\x7f", b"\x1b[31m"]


def mutate_bytes(rng: random.Random, data: bytes) -> tuple[bytes, str]:
    op = rng.choice(["insert", "insert", "crlf", "cr", "long-line", "truncate-bytes", "bom", "encoding",
                     "ctrl-z-end", "no-final-newline", "nul-run"])
    if op == "insert":
        b = rng.choice(BYTE_INSERTS)
        k = rng.randrange(len(data) + 1)
        return data[:k] + b + data[k:], f"insert {b!r}@{k}"
    if op == "crlf":
        return data.replace(b"\r\n", b"\n").replace(b"\n", b"\r\n"), op
    if op == "cr":
        return data.replace(b"\r\n", b"\n").replace(b"\n", b"\r"), op
    if op == "long-line":
        unit = rng.choice([b"X1 ", b"1", b" ", b"G01 ", b"(", b";", b"R1=R1+1 ", b"\"x", b"N1 "])
        k = rng.randrange(len(data) + 1)
        return data[:k] + unit * rng.choice([1000, 30000, 200000]) + data[k:], f"long-line {unit!r}"
    if op == "truncate-bytes":
        k = rng.randrange(len(data) + 1)
        return data[:k], f"truncate@{k}"
    if op == "bom":
        return rng.choice([b"\xef\xbb\xbf", b"\xff\xfe", b"\xfe\xff"]) + data, op
    if op == "encoding":
        enc = rng.choice(["utf-16", "utf-16-be", "cp1250", "latin-1", "utf-32"])
        try:
            return data.decode("utf-8", "replace").encode(enc, "replace"), f"encoding {enc}"
        except Exception:  # noqa: BLE001
            return data, op
    if op == "ctrl-z-end":
        return data + b"\x1a", op
    if op == "no-final-newline":
        return data.rstrip(b"\r\n"), op
    k = rng.randrange(len(data) + 1)
    return data[:k] + b"\x00" * rng.choice([1, 16, 4096]) + data[k:], op


def mutate_program(rng: random.Random, text: str, dialect: str, grammar_line=None) -> tuple[bytes, list[str], int | None]:
    """Mutations of one program; the last element is the line of a sole injected error, if any."""
    tok = VOCAB.get(dialect, _tok_cnc8x6)
    lines = _split(text)
    if rng.random() < 0.12:  # the injected-error oracle: one unknown code on its own line, nothing else
        k = rng.randrange(len(lines) + 1)
        bad = rng.choice(BAD_TOKENS)
        if dialect == "isg" and k < len(lines) and lines[k].lstrip().startswith("%"):
            k += 1  # keep it out of a header's title
        lines.insert(k, f"N{9000 + k} {bad}" if dialect != "sinumerik" else bad)
        return "\n".join(lines).encode("utf-8"), [f"inject {bad} at line {k + 1}"], k + 1
    notes = []
    for _ in range(rng.choice([1, 1, 1, 2, 2, 3, 5, 8])):
        notes.append(mutate_lines(rng, lines, tok, grammar_line))
    data = "\n".join(lines).encode("utf-8")
    if rng.random() < 0.25:
        data, note = mutate_bytes(rng, data)
        notes.append(note)
    return data, notes, None


# -------------------------------------------------------------------------------------------------
# TOML writing (valid and deliberately odd)

class Raw(str):
    """A value written verbatim into TOML (dates, malformed values)."""


def toml_value(v) -> str:
    if isinstance(v, Raw):
        return str(v)
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_key(k)} = {toml_value(x)}" for k, x in v.items()) + "}"
    return str(v)


def _key(k: str) -> str:
    return k if re.fullmatch(r"[A-Za-z0-9_-]+", k) else toml_value(k)


def toml_dump(setup: dict, rng: random.Random | None = None) -> str:
    """Tables in the usual layout; with ``rng`` sometimes dotted keys or inline tables instead."""
    out = []
    style = rng.choice(["plain"] * 6 + ["dotted", "inline", "comments"]) if rng else "plain"
    for name, tab in setup.items():
        if isinstance(tab, list) and all(isinstance(t, dict) for t in tab) and tab:
            for t in tab:
                out.append(f"\n[[{_key(name)}]]")
                for k, v in t.items():
                    out.append(f"{_key(k)} = {toml_value(v)}")
        elif isinstance(tab, dict):
            subs = {k: v for k, v in tab.items() if isinstance(v, dict)}
            if style == "dotted":
                out.insert(0, "\n".join(f"{_key(name)}.{_key(k)} = {toml_value(v)}" for k, v in tab.items()
                                        if not isinstance(v, dict)))
            elif style == "inline" and name != "machine":
                out.insert(0, f"{_key(name)} = {toml_value({k: v for k, v in tab.items() if not isinstance(v, dict)})}")
            else:
                out.append(f"\n[{_key(name)}]" + ("   # table" if style == "comments" else ""))
                for k, v in tab.items():
                    if not isinstance(v, dict):
                        out.append(f"{_key(k)} = {toml_value(v)}" + ("  # c" if style == "comments" else ""))
            for k, v in subs.items():
                out.append(f"\n[{_key(name)}.{_key(k)}]")
                for kk, vv in v.items():
                    out.append(f"{_key(kk)} = {toml_value(vv)}")
        else:
            out.insert(0, f"{_key(name)} = {toml_value(tab)}")
    return "\n".join(out).lstrip("\n") + "\n"


# -------------------------------------------------------------------------------------------------
# meshes for mesh stocks and design checks (ASCII STL written by hand: no dependency)

def stl_box(x0, x1, y0, y1, z0, z1, drop: int = 0, flip: bool = False) -> bytes:
    v = [(x, y, z) for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    tris = []
    for a, b, c, d in quads:
        tris += [(a, b, c), (a, c, d)]
    if flip:
        tris = [(a, c, b) for a, b, c in tris]
    tris = tris[drop:]
    lines = ["solid box"]
    for t in tris:
        lines.append(" facet normal 0 0 0\n  outer loop")
        lines += [f"   vertex {v[i][0]} {v[i][1]} {v[i][2]}" for i in t]
        lines.append("  endloop\n endfacet")
    lines.append("endsolid box")
    return ("\n".join(lines) + "\n").encode()


def random_mesh_file(rng: random.Random, bbox) -> tuple[bytes, str]:
    x0, x1, y0, y1, z0, z1 = bbox
    c = rng.random()
    if c < 0.5:
        return stl_box(x0, x1, y0, y1, z0, z1), "box.stl"
    if c < 0.6:
        return stl_box(x0, x1, y0, y1, z0, z1, drop=rng.randint(1, 4)), "open box.stl"
    if c < 0.65:
        return stl_box(x0, x1, y0, y1, z0, z1, flip=True), "inside-out box.stl"
    if c < 0.7:
        return b"", "empty file"
    if c < 0.75:
        return b"solid x\nendsolid x\n", "no facets"
    if c < 0.8:
        return bytes(rng.randrange(256) for _ in range(rng.choice([10, 84, 200]))), "random bytes"
    if c < 0.85:
        return b"\x00" * 80 + (10).to_bytes(4, "little"), "binary STL header claiming 10 triangles"
    if c < 0.9:
        return stl_box(x0, x0, y0, y1, z0, z1), "flat box"
    return stl_box(x0, x1, y0, y1, z0, z1) + stl_box(x0 + 1, x1 + 1, y0, y1, z0, z1)[0:], "two overlapping boxes"


# -------------------------------------------------------------------------------------------------
# grammar generators: plausible programs on small stocks

@dataclass
class Gen:
    dialect: str
    machine: str
    program: str
    setup: dict
    extra: dict[str, bytes] = field(default_factory=dict)
    program_name: str = "prog.nc"


def _lathe_setup(rng: random.Random, dialect: str) -> tuple[dict, float, float, float]:
    d = _r(rng, 6, 30, 1)
    length = _r(rng, 4, 20, 1)
    z0 = rng.choice([-length, -length / 2, 0.0])
    z0 = round(z0, 1)
    z1 = round(z0 + length, 1)
    diam = True if dialect == "cnc8x6" else rng.random() < 0.5
    m: dict = {"kind": "lathe", "dialect": dialect}
    if rng.random() < 0.6:
        m["diameter_programming"] = diam
    else:
        diam = dialect == "cnc8x6"
    if rng.random() < 0.2:
        m["m03"] = rng.choice(["positive", "negative"])
    if rng.random() < 0.7:
        m["start"] = [round((d + 10) * (2 if diam else 1) / 2, 1) * (1 if not diam else 1), 0.0, z1 + 5]
        if diam:
            m["start"][0] = round(d + 10, 1)
    stock: dict
    c = rng.random()
    if c < 0.75:
        stock = {"shape": "cylinder", "diameter": d, "z": [z0, z1]}
    elif c < 0.95:
        r = d / 2
        zm = round((z0 + z1) / 2, 1)
        prof = [[0.0, z0], [r, z0], [r, zm], [round(r * rng.uniform(0.5, 0.95), 2), zm],
                [round(r * rng.uniform(0.5, 0.95), 2), z1], [0.0, z1]]
        if rng.random() < 0.5:
            prof.reverse()
        stock = {"shape": "revolve", "profile": prof}
    else:
        stock = {"shape": "box", "x": [-d / 2, d / 2], "y": [-d / 2, d / 2], "z": [z0, z1]}
    tools = []
    for i in range(rng.choice([1, 1, 2, 3])):
        kind = rng.choice(["thread", "thread", "turning", "turning", "profile"])
        t: dict = {"number": i + 1, "kind": kind} if rng.random() < 0.9 else {"kind": kind}
        if kind in ("thread", "turning"):
            if rng.random() < 0.7:
                t["angle"] = _r(rng, 20, 90, 1)
            if rng.random() < 0.5:
                t["tip_radius"] = _r(rng, 0, 0.5, 2)
            if rng.random() < 0.2:
                t["height"] = _r(rng, 1, 12, 1)
            if rng.random() < 0.2:
                t["thickness"] = _r(rng, 0.5, 6, 1)
        else:
            w = _r(rng, 0.5, 3, 2)
            h = _r(rng, 1, 8, 2)
            pts = [[0.0, 0.0], [w, h], [-w, h]] if rng.random() < 0.6 else \
                [[-w / 2, 0.0], [w / 2, 0.0], [w, h], [-w, h]]
            t["points"] = pts
        tools.append(t)
    setup = {"machine": m, "stock": stock, "tool": tools}
    if dialect == "cnc8x6" and rng.random() < 0.7:
        m["constants"] = {"8": rng.choice([112500, 118000, -112500, 130000, 4000000, 4160000, 15160000, 160000])}
        if rng.random() < 0.5:
            setup["parameters"] = {rng.choice(["R04", "R15", "R16"]): rng.choice([120.0, -120.0, 115.0, 130.5])}
    sim: dict = {}
    if rng.random() < 0.5:
        sim["max_blocks"] = rng.choice([100, 1000, 20000])
    if rng.random() < 0.2:
        sim["tolerance"] = rng.choice([0.05, 0.1, 0.02])
    if rng.random() < 0.1:
        sim["fail_on_warning"] = rng.choice([True, False])
    if sim:
        setup["simulation"] = sim
    return setup, d, z0, z1


def _xstr(x: float, diam: bool) -> str:
    return fmt_num(x * (2 if diam else 1), 3)


def gen_cnc8x6_lathe(rng: random.Random) -> Gen:
    setup, d, z0, z1 = _lathe_setup(rng, "cnc8x6")
    diam = setup["machine"].get("diameter_programming", True)
    r = d / 2
    lines, n = [], [5]

    def N() -> str:
        n[0] += 5
        return f"N{n[0]}"

    ntools = len(setup["tool"])
    lines.append(f"{N()} G00 G95 T{rng.randint(1, ntools)} S{rng.choice([50, 500, 1000])} "
                 f"{rng.choice(['M03', 'M03', 'M04', 'M05', ''])} \"START")
    x, z = r + 3, z1 + 2
    lines.append(f"{N()} G00 X{_xstr(x, diam)} Z{fmt_num(z)}")
    for _ in range(rng.randint(1, 6)):
        c = rng.random()
        if c < 0.3:  # thread
            xr = _r(rng, r * 0.7, r * 1.05)
            lines.append(f"{N()} G00 X{_xstr(xr, diam)} Z{fmt_num(z1 + _r(rng, 0.5, 3))}")
            ze = _r(rng, z0 - 1, z1 - 1)
            lead = rng.choice([0.5, 1.0, 1.5, 2.0, _r(rng, 0.2, 6), _r(rng, 0.01, 99.99)])
            words = [f"G33 Z{fmt_num(ze)}", f"F{fmt_num(lead)}"]
            if rng.random() < 0.4:
                words.append(f"I{fmt_num(_r(rng, 0, 359, 1))}")
            je = False
            if rng.random() < 0.3:
                words.append(f"J{fmt_num(_r(rng, 0.5, 4, 1), point=True)}")
                je = True
            if rng.random() < 0.2:
                words.append(f"E{fmt_num(_r(rng, 0.5, 3, 1), point=True)}" + ("" if "." in fmt_num(1.5) else "."))
                je = True
            rng.shuffle(words)
            lines.append(f"{N()} " + " ".join(words))
            if je:
                lines.append(f"{N()} \"EMPTY")
                lines.append(f"{N()} G00 X{_xstr(r + 3, diam)} Z{fmt_num(z1 + 2)}")
            else:
                lines.append(f"{N()} G00 X{_xstr(r + 3, diam)}")
                lines.append(f"{N()} Z{fmt_num(z1 + 2)}")
            x, z = r + 3, z1 + 2
        elif c < 0.6:  # feed move
            xn = _r(rng, r * 0.4, r * 1.2)
            zn = _r(rng, z0 - 1, z1 + 1)
            lines.append(f"{N()} G01 X{_xstr(xn, diam)} Z{fmt_num(zn)} F{fmt_num(_r(rng, 0.05, 0.5))}")
            x, z = xn, zn
        elif c < 0.8:  # arc in ZX: I radius increment, K increment
            rad = _r(rng, 0.5, max(0.6, r / 2))
            ang0 = rng.uniform(0, 2 * math.pi)
            ci, ck = -rad * math.cos(ang0), -rad * math.sin(ang0)
            ang1 = ang0 + rng.uniform(-math.pi, math.pi)
            xe, ze = x + ci + rad * math.cos(ang1), z + ck + rad * math.sin(ang1)
            if xe < 0.1:
                continue
            lines.append(f"{N()} {rng.choice(['G02', 'G03'])} X{_xstr(xe, diam)} Z{fmt_num(ze)} "
                         f"I{fmt_num(ci)} K{fmt_num(ck)} F0.1")
            x, z = xe, ze
        elif c < 0.9:  # parameters
            p = rng.randint(1, 79)
            lines.append(f"{N()} R{p:02d}={fmt_num(_r(rng, -5, 5))}")
        else:  # a jump loop
            target = n[0] - 5 * rng.randint(0, 2)
            lines.append(f"{N()} G73 L{max(10, target)} Q{rng.randint(0, 3)}")
    lines.append(f"{N()} G00 X{_xstr(r + 10, diam)} Z{fmt_num(z1 + 5)} M05")
    if rng.random() < 0.5:
        lines.append(f"{N()} M30")
    return Gen("cnc8x6", "lathe", "\n".join(lines) + "\n", setup)


def _mill_setup(rng: random.Random, dialect: str) -> tuple[dict, tuple]:
    w, h = _r(rng, 10, 40, 1), _r(rng, 10, 40, 1)
    dep = _r(rng, 3, 10, 1)
    x0, y0 = rng.choice([0.0, -w / 2]), rng.choice([0.0, -h / 2])
    bbox = (round(x0, 2), round(x0 + w, 2), round(y0, 2), round(y0 + h, 2), -dep, 0.0)
    m: dict = {"kind": "mill", "dialect": dialect}
    if rng.random() < 0.7:
        m["start"] = [round(x0 - 5, 1), round(y0 - 5, 1), 10.0]
    if rng.random() < 0.1:
        m["rapid"] = rng.choice([5000.0, 20000])
    stock = {"shape": "box", "x": [bbox[0], bbox[1]], "y": [bbox[2], bbox[3]], "z": [-dep, 0.0]}
    extra = {}
    if rng.random() < 0.05:
        data, _ = random_mesh_file(rng, bbox)
        extra["blank.stl"] = data
        stock = {"shape": "mesh", "path": "blank.stl"}
    tools = []
    for i in range(rng.choice([1, 1, 2, 3])):
        kind = rng.choice(["endmill", "endmill", "ballmill"])
        t: dict = {"number": i + 1, "kind": kind, "diameter": rng.choice([2.0, 3.0, 4.0, 6.0, _r(rng, 1, 8, 1)])}
        if rng.random() < 0.5:
            t["length"] = _r(rng, 5, 30, 1)
        if kind == "endmill" and rng.random() < 0.2:
            t["corner_radius"] = round(t["diameter"] / rng.choice([4, 3, 2.5]), 2)
        if kind == "endmill" and rng.random() < 0.1:
            t["center_cutting"] = False
        tools.append(t)
    setup = {"machine": m, "stock": stock, "tool": tools}
    sim: dict = {}
    if rng.random() < 0.5:
        sim["max_blocks"] = rng.choice([100, 1000, 20000])
    if sim:
        setup["simulation"] = sim
    if rng.random() < 0.08:
        setup["check"] = [random_check(rng, "mill", bbox)]
    return setup, bbox, extra


def random_check(rng: random.Random, kind: str, bbox) -> dict:
    x0, x1, y0, y1, z0, z1 = bbox
    cx, cy = _r(rng, x0, x1), _r(rng, y0, y1)
    if kind == "mill":
        c = rng.choice(["depth", "pocket", "slot", "volume"])
        if c == "depth":
            return {"kind": "depth", "at": [cx, cy], "z": _r(rng, z0, z1)}
        if c == "pocket":
            return {"kind": "pocket", "at": [cx, cy], "size": [_r(rng, 1, 20), _r(rng, 1, 20)], "floor": _r(rng, z0, z1)}
        if c == "slot":
            return {"kind": "slot", "at": [cx, cy], "direction": rng.choice(["x", "y", "z", "q"]), "width": _r(rng, 1, 10),
                    "floor": _r(rng, z0, z1)}
        return {"kind": "volume", "removed": _r(rng, 0, 1000), "tolerance": _r(rng, 0, 10)}
    c = rng.choice(["diameter", "thread", "ramp"])
    if c == "diameter":
        return {"kind": "diameter", "z": _r(rng, z0, z1), "expected": _r(rng, 1, 30)}
    if c == "thread":
        return {"kind": "thread", "z": [z0, z1], "lead": _r(rng, 0.5, 3)}
    return {"kind": "ramp", "z": [z0, z1], "radius": [_r(rng, 1, 10), _r(rng, 1, 10)]}


def gen_cnc8x6_mill(rng: random.Random) -> Gen:
    setup, bbox, extra = _mill_setup(rng, "cnc8x6")
    x0, x1, y0, y1, z0, z1 = bbox
    lines, n = [], [0]

    def N() -> str:
        n[0] += 10
        return f"N{n[0]}"

    lines.append(f"{N()} G00 G17 G90 T{rng.randint(1, len(setup['tool']))} S1000 M03")
    x, y = _r(rng, x0 - 5, x1 + 5), _r(rng, y0 - 5, y1 + 5)
    lines.append(f"{N()} G00 X{fmt_num(x)} Y{fmt_num(y)} Z5")
    depth = _r(rng, z0 * 0.8, 0.5)
    lines.append(f"{N()} G01 Z{fmt_num(depth)} F100")
    for _ in range(rng.randint(1, 7)):
        c = rng.random()
        if c < 0.4:
            x, y = _r(rng, x0 - 3, x1 + 3), _r(rng, y0 - 3, y1 + 3)
            words = [f"X{fmt_num(x)}", f"Y{fmt_num(y)}"]
            if rng.random() < 0.3:
                depth = _r(rng, z0 * 0.9, 0.5)
                words.append(f"Z{fmt_num(depth)}")
            lines.append(f"{N()} G01 " + " ".join(words) + (f" F{rng.randint(50, 500)}" if rng.random() < 0.3 else ""))
        elif c < 0.7:
            rad = _r(rng, 1, 10)
            a0 = rng.uniform(0, 2 * math.pi)
            ci, cj = -rad * math.cos(a0), -rad * math.sin(a0)
            a1 = a0 + rng.uniform(-2 * math.pi, 2 * math.pi)
            xe, ye = x + ci + rad * math.cos(a1), y + cj + rad * math.sin(a1)
            lines.append(f"{N()} {rng.choice(['G02', 'G03'])} X{fmt_num(xe)} Y{fmt_num(ye)} I{fmt_num(ci)} J{fmt_num(cj)}")
            x, y = xe, ye
        elif c < 0.85:  # helix
            pitch = _r(rng, 0.2, 3)
            rad = _r(rng, 1, 8)
            lines.append(f"{N()} Z{fmt_num(pitch, point=True)} G10")
            q = rng.randint(0, 3)
            lab = n[0] + 10
            lines.append(f"{N()} G09 {rng.choice(['G02', 'G03'])} X{fmt_num(x)} Y{fmt_num(y)} I{fmt_num(rad)}"
                         + (f" G73 L{lab} Q{q}" if rng.random() < 0.5 else ""))
            lines.append(f"{N()} G98")
        else:
            lines.append(f"{N()} G73 L{max(10, n[0] - 10 * rng.randint(0, 2))} Q{rng.randint(0, 3)}")
    lines.append(f"{N()} G00 Z20")
    if rng.random() < 0.5:
        lines.append(f"{N()} M30")
    return Gen("cnc8x6", "mill", "\n".join(lines) + "\n", setup, extra)


def gen_isg_lathe(rng: random.Random) -> Gen:
    setup, d, z0, z1 = _lathe_setup(rng, "isg")
    diam_setup = setup["machine"].get("diameter_programming", False)
    r = d / 2
    body, subs = [], []
    diam = diam_setup
    nn = [0]

    def N() -> str:
        nn[0] += 5
        return f"N{nn[0]}"

    if rng.random() < 0.5:
        body.append(f"{N()} G51 ;Durchmesser")
        diam = True
    elif rng.random() < 0.2:
        body.append(f"{N()} G52")
        diam = False
    body.append(f"{N()} T{rng.randint(1, len(setup['tool']))} D1 {rng.choice(['M03', 'M03', 'M04', ''])} S{rng.randint(10, 500)}")
    body.append(f"{N()} G00 X{_xstr(r + 2, diam)} Z{fmt_num(z1 + 3)}")
    names = []
    for _ in range(rng.randint(1, 5)):
        c = rng.random()
        if c < 0.35:
            xr = _r(rng, r * 0.75, r * 1.02)
            body.append(f"{N()} G01 X{_xstr(xr, diam)} F{rng.randint(100, 1000)}")
            ze = _r(rng, z0 - 1, z1 - 1)
            w = f"{N()} G33 Z{fmt_num(ze)} K{fmt_num(rng.choice([1.5, 1.0, _r(rng, 0.2, 5)]))}"
            if rng.random() < 0.5:
                w += rng.choice([" S.OFFSET=", " S.OFFSET ", " s.offset="]) + fmt_num(_r(rng, 0, 359.9, 1))
            body.append(w)
            body.append(f"{N()} G00 X{_xstr(r + 2, diam)}")
            body.append(f"{N()} Z{fmt_num(z1 + 3)}")
        elif c < 0.6:
            body.append(f"{N()} G01 X{_xstr(_r(rng, r * 0.4, r * 1.1), diam)} Z{fmt_num(_r(rng, z0, z1 + 1))} F300")
        elif c < 0.75:
            body.append(f"{N()} G00 X{_xstr(r + 2, diam)} Z{fmt_num(z1 + 2)}")
            body.append(f"{N()} G01 X{_xstr(r * 0.8, diam)} F300")
            rad = _r(rng, 0.5, r / 3)
            body.append(f"{N()} {rng.choice(['G02', 'G03'])} X{_xstr(r * 0.8, diam)} Z{fmt_num(z1 - 2 * rad)} "
                        f"I0 K{fmt_num(-rad)}")
            body.append(f"{N()} G00 X{_xstr(r + 2, diam)}")
        else:
            name = rng.choice(["Gewinde", "L\u00e4ngsgewinde", "SUB_1", "Sub"])
            if name not in names:
                names.append(name)
                sb = [f"%L {name}", f"N100 G00 X{_xstr(r + 2, diam)} Z{fmt_num(z1 + 2)}",
                      f"N110 G01 X{_xstr(r * 0.9, diam)} F200", f"N120 G33 Z{fmt_num(z0 + 1)} K1.5",
                      f"N130 G00 X{_xstr(r + 2, diam)}", f"N140 {rng.choice(['M29', 'M17'])}"]
                subs.append("\n".join(sb))
            body.append(f"{N()} LL {name}")
    body.append(f"{N()} M05 X{_xstr(r + 10, diam)} Z{fmt_num(z1 + 10)}")
    if rng.random() < 0.85:
        body.append(f"{N()} M30")
    head = "%MAIN (fuzz)" if rng.random() < 0.7 else ("%" + rng.choice(["G33", "P1", "x"]))
    parts = [head + "\n" + "\n".join(body)]
    if subs:
        if rng.random() < 0.5:
            parts = subs + parts
        else:
            parts = parts + subs
    if rng.random() < 0.2:  # no header at all: one main program
        parts = ["\n".join(body)] + subs if not subs else parts
    return Gen("isg", "lathe", "\n\n".join(parts) + "\n", setup)


ISG_EXTERNAL = ["VENDOR_CYC.nc", "G803", "0_Start.nc"]


def _isg_mill_piece(rng: random.Random, bbox, N, locals_: list[str]) -> list[str]:
    """One random feature of a real ISG milling program (loops, V.P. variables, compensation, #CS and
    #ROTATION about Z, G21/G22/G351 mirroring, G68, local and external subprograms, a cycle call)."""
    x0, x1, y0, y1, z0, _ = bbox
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    dz = fmt_num(_r(rng, max(z0, -4), -0.2))
    c = rng.random()
    if c < 0.15:  # a $FOR/$WHILE loop of passes
        k = rng.randint(1, 4)
        if rng.random() < 0.5:
            return [f"{N()} $FOR P1 = 0, {k}, 1", f"{N()}   G01 X[{fmt_num(x0)} + P1 * {fmt_num((x1 - x0) / (k + 1))}] "
                    f"Y{fmt_num(_r(rng, y0, y1))} Z{dz} F300", f"{N()} $ENDFOR"]
        return [f"{N()} #VAR", f"{N()}   V.P.CNT = 0", f"{N()} #ENDVAR", f"{N()} $WHILE V.P.CNT < {k}",
                f"{N()}   G01 Y[{fmt_num(y0)} + V.P.CNT * {fmt_num((y1 - y0) / (k + 1))}] Z{dz} F300",
                f"{N()}   V.P.CNT = V.P.CNT + 1", f"{N()} $ENDWHILE"]
    if c < 0.3:  # a rectangle under radius compensation
        ax, bx = sorted([_r(rng, x0, x1), _r(rng, x0, x1)])
        ay, by = sorted([_r(rng, y0, y1), _r(rng, y0, y1)])
        return [f"{N()} G00 X{fmt_num(ax - 5)} Y{fmt_num(ay - 5)}", f"{N()} G01 Z{dz} F200",
                f"{N()} {rng.choice(['G41', 'G42'])} X{fmt_num(ax)} Y{fmt_num(ay)}", f"{N()} X{fmt_num(bx)}",
                f"{N()} Y{fmt_num(by)}", f"{N()} X{fmt_num(ax)}", f"{N()} Y{fmt_num(ay)}",
                f"{N()} G40 X{fmt_num(ax - 5)} Y{fmt_num(ay - 5)}", f"{N()} G00 Z5"]
    if c < 0.5:  # a transformation about Z: #CS, #ROTATION, G68 or mirroring, then a small square and an arc
        kind = rng.choice(["cs", "rot", "g68", "g21", "g22", "g351"])
        ang = fmt_num(_r(rng, -180, 180, 1))
        on, off = {
            "cs": (f"#CS ON [{fmt_num(cx)}, {fmt_num(cy)}, 0, 0, 0, {ang}]", "#CS OFF"),
            "rot": (f"#ROTATION ON [ANGLE = {ang} CENTER1 = {fmt_num(cx)} CENTER2 = {fmt_num(cy)}]", "#ROTATION OFF"),
            "g68": (f"G68 R{ang} X{fmt_num(cx)} Y{fmt_num(cy)}", "G69"),
            "g21": ("G21", "G20"), "g22": ("G22", "G20"),
            "g351": (rng.choice(["G351 X-1", "G351 Y-1", "G351 X-1 Y-1"]), "G351 X1 Y1"),
        }[kind]
        r = _r(rng, 1, 6)
        return [f"{N()} {on}", f"{N()} G00 X{fmt_num(r)} Y0", f"{N()} G01 Z{dz} F200", f"{N()} Y{fmt_num(r)}",
                f"{N()} {rng.choice(['G02', 'G03'])} X0 Y{fmt_num(2 * r)} {rng.choice(['I0 J' + fmt_num(r), 'R' + fmt_num(r)])}",
                f"{N()} G00 Z5", f"{N()} {off}"]
    if c < 0.65:  # a local subprogram
        name = rng.choice(["UP1", "Kontur", "sub_a"])
        if name not in locals_:
            locals_.append(name)
        return [f"{N()} LL {name}"]
    if c < 0.75:  # a vendor subprogram or implicit call (declared external or not)
        return [f"{N()} " + rng.choice(["L VENDOR_CYC.nc", "L C:\\Users\\cnc\\0_Start.nc", "G803",
                                         "L CYCLE [NAME = VENDOR_CYC.nc @P1 = 5]", "L MISSING.nc", "G805[1, 2]"])]
    if c < 0.85:  # an arc in the plane
        rad = _r(rng, 1, 8)
        return [f"{N()} G00 X{fmt_num(cx - rad)} Y{fmt_num(cy)}", f"{N()} G01 Z{dz} F200",
                f"{N()} {rng.choice(['G02', 'G03'])} X{fmt_num(cx + rad)} Y{fmt_num(cy)} I{fmt_num(rad)} J0",
                f"{N()} G00 Z5"]
    return [f"{N()} " + _tok_isg_mill(rng) for _ in range(rng.randint(1, 3))]


def _tok_isg_mill(rng: random.Random) -> str:
    return rng.choice(["#CS ON [1, 2, 0, 0, 0, 45]", "#CS ON [0, 0, 0, 10, 0, 0]", "#CS OFF", "#CS OFF ALL",
                       "#ROTATION ON [ANGLE = 30]", "#ROTATION ON [ANGLE 1/0]", "#ROTATION OFF", "G68 R30",
                       "G69", "G21", "G22", "G23", "G20", "G351 X-1", "G351 X2", "G351", "#MIRROR ON [X]",
                       "#FLUSH WAIT", "#MSG [\"x\"]", "#HSC ON", "#HSC OFF", "#DISABLE MODAL CYCLE",
                       "L CYCLE [NAME = VENDOR_CYC.nc MODAL_MOVE]", "G54", "G92 X0 Y0", "G41", "G40", "D1",
                       "V.P.A = 1", "#VAR V.P.A #ENDVAR", "$IF V.P.A == 1", "$ENDIF", "G81", "G80", "G803"])


def gen_isg_mill(rng: random.Random) -> Gen:
    setup, bbox, extra = _mill_setup(rng, "isg")
    x0, x1, y0, y1, z0, _ = bbox
    if rng.random() < 0.7:
        setup["machine"]["external_subprograms"] = rng.sample(ISG_EXTERNAL, rng.randint(1, len(ISG_EXTERNAL)))
    nn = [0]

    def N() -> str:
        nn[0] += 10
        return f"N{nn[0]}"

    tool = rng.randint(1, len(setup["tool"]))
    body = [f"{N()} G17 G90 T{tool} D1 M06", f"{N()} M03 S{rng.randint(500, 5000)} F{rng.randint(100, 800)}",
            f"{N()} G00 X{fmt_num(x0 - 3)} Y{fmt_num(y0 - 3)} Z5"]
    locals_: list[str] = []
    for _ in range(rng.randint(1, 5)):
        body += _isg_mill_piece(rng, bbox, N, locals_)
    body += [f"{N()} G00 Z20", f"{N()} M30"]
    subs = []
    for name in locals_:
        dx, dy = _r(rng, -3, 3), _r(rng, -3, 3)
        subs.append(f"%L {name}\nN1 G91 G01 X{fmt_num(dx)} Y{fmt_num(dy)}\nN2 G90\nN3 M17")
    if rng.random() < 0.3:
        extra["VENDOR_CYC.nc"] = b"N1 G91 G01 X1 Y1\nN2 G90\nN3 M17\n"
    head = rng.choice(["%MAIN", "% main", "%fuzz (ISG mill)", ""])
    text = (head + "\n" if head else "") + "\n".join(body) + ("\n\n" + "\n\n".join(subs) if subs else "")
    return Gen("isg", "mill", text + "\n", setup, extra)


def _cycle_call(rng: random.Random, name: str, bbox, tool_d: float, contour: str | None = None) -> str:
    x0, x1, y0, y1, z0, z1 = bbox
    cx, cy = _r(rng, x0 + (x1 - x0) * 0.3, x1 - (x1 - x0) * 0.3), _r(rng, y0 + (y1 - y0) * 0.3, y1 - (y1 - y0) * 0.3)
    size = min(x1 - x0, y1 - y0)
    dp = _r(rng, max(z0, -5), -0.5)
    mid = rng.choice(["", 0, _r(rng, 0.5, 3)])
    cdir = rng.randint(0, 3)
    fal = rng.choice([0, 0, 0.2, 0.5])
    vari = rng.choice([0, 1, 2, 10, 11, 12, 20, 21, 22, 30, 31, 32])
    rtp, rfp, sdis = 5, 0, rng.choice([1, 2])
    if name == "POCKET1":
        leng, wid = _r(rng, tool_d * 1.2, size * 0.7), _r(rng, tool_d * 1.2, size * 0.6)
        p = [rtp, rfp, sdis, dp, "", leng, wid, _r(rng, tool_d / 2, wid / 2), cx, cy, _r(rng, 0, 90), 100, 300, mid,
             cdir, fal, vari % 20 if vari >= 20 else vari, "", ""]
    elif name == "POCKET2":
        p = [rtp, rfp, sdis, dp, "", _r(rng, tool_d / 2 * 1.1, size * 0.35), cx, cy, 100, 300, mid, cdir, fal,
             vari % 20 if vari >= 20 else vari]
    elif name == "POCKET3":
        leng, wid = _r(rng, tool_d * 1.2, size * 0.7), _r(rng, tool_d * 1.2, size * 0.6)
        p = [rtp, rfp, sdis, dp, leng, wid, _r(rng, tool_d / 2, wid / 2), cx, cy, _r(rng, 0, 90), mid, fal, 0, 300, 100,
             cdir, vari, rng.choice(["", _r(rng, tool_d * 0.3, tool_d * 0.9)]), "", "", "", "", ""]
    elif name == "POCKET4":
        p = [rtp, rfp, sdis, dp, _r(rng, tool_d / 2 * 1.1, size * 0.35), cx, cy, mid, fal, 0, 300, 100, cdir, vari,
             rng.choice(["", _r(rng, tool_d * 0.3, tool_d * 0.9)])]
    elif name == "SLOT1":
        wid = _r(rng, tool_d * 1.05, tool_d * 2)
        p = [rtp, rfp, sdis, dp, "", rng.randint(1, 4), _r(rng, wid * 1.1, size * 0.3), wid, cx, cy,
             _r(rng, 0, size * 0.1), _r(rng, 0, 90), rng.choice([0, 90, 120]), 100, 300, mid, cdir, fal,
             vari % 20 if vari >= 20 else vari]
    elif name == "SLOT2":
        wid = _r(rng, tool_d * 1.05, tool_d * 2)
        p = [rtp, rfp, sdis, dp, "", rng.randint(1, 3), _r(rng, 10, 100), wid, cx, cy, _r(rng, wid, size * 0.35),
             _r(rng, 0, 90), rng.choice([0, 120, 180]), 100, 300, mid, cdir, fal, vari % 20 if vari >= 20 else vari]
    elif name == "CYCLE71":
        p = [rtp, rfp, sdis, _r(rng, -1, -0.1), _r(rng, x0, cx), _r(rng, y0, cy), _r(rng, 5, size), _r(rng, 5, size),
             _r(rng, 0, 45), rng.choice(["", 0.5]), rng.choice(["", _r(rng, 0.5, tool_d)]), "", rng.choice([0, 0.2]),
             300, rng.choice([11, 12, 21, 22, 31, 32, 41, 42, 1, 2]), ""]
    else:  # CYCLE72
        p = [f'"{contour}"', rtp, rfp, sdis, dp, mid, fal, 0, 300, 100, rng.choice([1, 2, 11, 12]),
             rng.choice([40, 41, 42]), rng.choice([1, 2, 3]), _r(rng, 2, 8), 300, rng.choice([1, 2, 3]), _r(rng, 2, 8)]
    if rng.random() < 0.25:  # one parameter off
        k = rng.randrange(len(p))
        p[k] = _rand_param(rng)
    return f"{name}({', '.join(str(v) if not isinstance(v, float) else fmt_num(v) for v in p)})"


def gen_sinumerik_mill(rng: random.Random) -> Gen:
    setup, bbox, extra = _mill_setup(rng, "sinumerik")
    x0, x1, y0, y1, z0, z1 = bbox
    tool = rng.randint(1, len(setup["tool"]))
    tool_d = setup["tool"][tool - 1]["diameter"]
    if rng.random() < 0.3:
        setup["machine"]["external_subprograms"] = ["L_VENDOR", "SUB"]
    lines = [f"; fuzz program", "N10 G17 G90" + rng.choice(["", " G54", " G64"])]
    lines.append(rng.choice([f"N20 T{tool} D1 M6", f"N20 T{tool} D1\nN25 M6", f"N20 T{tool}"]))
    lines.append(f"N30 S{rng.randint(500, 5000)} {rng.choice(['M3', 'M3', 'M4', 'M5'])} F{rng.randint(100, 800)}")
    lines.append(f"N40 G0 X{fmt_num((x0 + x1) / 2)} Y{fmt_num((y0 + y1) / 2)} Z10")
    if rng.random() < 0.25:  # modal rounding after the positioning (a rounding at a rapid is not modelled)
        lines.append(f"N45 RNDM={fmt_num(_r(rng, 0.1, 1.5))}")
    tail: list[str] = []
    labels = []
    x, y = (x0 + x1) / 2, (y0 + y1) / 2
    for _ in range(rng.randint(1, 5)):
        c = rng.random()
        if c < 0.3:
            name = rng.choice(CYCLE_NAMES)
            contour = None
            if name == "CYCLE72":
                contour = rng.choice(["KONT", "A_K:E_K", "SUBK"])
                cl = _contour(rng, bbox)
                if ":" in contour:
                    a, b = contour.split(":")
                    tail += [f"{a}:"] + cl + [f"{b}:"]
                else:
                    tail += [f"PROC {contour}"] + cl + ["RET"]
            lines.append(_cycle_call(rng, name, bbox, tool_d, contour))
        elif c < 0.55:
            xe, ye = _r(rng, x0 - 2, x1 + 2), _r(rng, y0 - 2, y1 + 2)
            dz = _r(rng, z0 * 0.8, 1)
            lines.append(f"G1 Z{fmt_num(dz)}")
            corner = rng.choice(["", "", "", f" RND={fmt_num(_r(rng, 0.1, 2))}", f" CHF={fmt_num(_r(rng, 0.1, 2))}",
                                 f" CHR={fmt_num(_r(rng, 0.1, 2))}"])
            lines.append(f"G1 X{fmt_num(xe)} Y{fmt_num(ye)}{corner}" if rng.random() < 0.7 else
                         f"G1 X=IC({fmt_num(xe - x)}) Y=AC({fmt_num(ye)}){corner}")
            x, y = xe, ye
        elif c < 0.7:
            rad = _r(rng, 1, 8)
            a0 = rng.uniform(0, 2 * math.pi)
            a1 = a0 + rng.uniform(-math.pi * 0.95, math.pi * 0.95)
            ci, cj = -rad * math.cos(a0), -rad * math.sin(a0)
            xe, ye = x + ci + rad * math.cos(a1), y + cj + rad * math.sin(a1)
            g = rng.choice(["G2", "G3"])
            if rng.random() < 0.5:
                lines.append(f"{g} X{fmt_num(xe)} Y{fmt_num(ye)} I{fmt_num(ci)} J{fmt_num(cj)}")
            else:
                lines.append(f"{g} X{fmt_num(xe)} Y{fmt_num(ye)} CR={fmt_num(rad * rng.choice([1, -1]))}")
            x, y = xe, ye
        elif c < 0.8:  # a counted loop with R parameters
            lab = f"LOOP{len(labels)}"
            labels.append(lab)
            k = rng.randint(1, 4)
            lines += [f"R{len(labels)}=0", f"{lab}:", f"G1 X{fmt_num(_r(rng, x0, x1))} Y={fmt_num(_r(rng, y0, y1))}+R{len(labels)}*0.5",
                      f"R{len(labels)}=R{len(labels)}+1", f"IF R{len(labels)}<{k} GOTOB {lab}"]
        elif c < 0.88:
            lab = f"REP{len(labels)}"
            labels.append(lab)
            lines += [f"{lab}:", f"G1 X{fmt_num(_r(rng, x0, x1))} Y{fmt_num(_r(rng, y0, y1))}", f"REPEAT {lab} P={rng.randint(0, 3)}"]
        elif c < 0.95:  # radius compensation around a rectangle
            ax, bx = sorted([_r(rng, x0, x1), _r(rng, x0, x1)])
            ay, by = sorted([_r(rng, y0, y1), _r(rng, y0, y1)])
            lines += [f"G0 X{fmt_num(ax - 5)} Y{fmt_num(ay - 5)}", "G1 Z-1",
                      f"{rng.choice(['G41', 'G42'])} G1 X{fmt_num(ax)} Y{fmt_num(ay)}", f"X{fmt_num(bx)}",
                      f"Y{fmt_num(by)}", f"X{fmt_num(ax)}", f"Y{fmt_num(ay)}", f"G40 G1 X{fmt_num(ax - 5)} Y{fmt_num(ay - 5)}"]
        else:  # subprogram
            name = rng.choice(["SUBA", "SUBB"])
            lines.append(f"{name}" + (f" P{rng.randint(1, 3)}" if rng.random() < 0.4 else ""))
            sub = [f"G91 G1 X{fmt_num(_r(rng, -3, 3))} Y{fmt_num(_r(rng, -3, 3))}", "G90"]
            if rng.random() < 0.5:
                if f"PROC {name}" not in tail:
                    tail += [f"PROC {name}"] + sub + ["RET"]
            else:
                extra[f"{name}.spf"] = ("\n".join(sub + ["M17"]) + "\n").encode()
    lines.append("G0 Z20")
    lines.append(rng.choice(["M30", "M30", "M2", ""]))
    return Gen("sinumerik", "mill", "\n".join(lines + [""] + tail) + "\n", setup, extra, "prog.mpf")


def _contour(rng: random.Random, bbox) -> list[str]:
    x0, x1, y0, y1, _, _ = bbox
    ax, bx = sorted([_r(rng, x0 - 2, x1 + 2), _r(rng, x0 - 2, x1 + 2)])
    ay, by = sorted([_r(rng, y0 - 2, y1 + 2), _r(rng, y0 - 2, y1 + 2)])
    if rng.random() < 0.5:
        return [f"G1 X{fmt_num(ax)} Y{fmt_num(ay)}", f"X{fmt_num(bx)}", f"Y{fmt_num(by)}", f"X{fmt_num(ax)}",
                f"Y{fmt_num(ay)}"]
    r = _r(rng, 0.5, max(0.6, min(bx - ax, by - ay) / 2))
    return [f"G1 X{fmt_num(ax + r)} Y{fmt_num(ay)}", f"X{fmt_num(bx - r)}",
            f"G3 X{fmt_num(bx)} Y{fmt_num(ay + r)} CR={fmt_num(r)}", f"G1 Y{fmt_num(by - r)}",
            f"G3 X{fmt_num(bx - r)} Y{fmt_num(by)} I=AC({fmt_num(bx - r)}) J=AC({fmt_num(by - r)})",
            f"G1 X{fmt_num(ax)}", f"Y{fmt_num(ay)}"]


GENERATORS = [gen_cnc8x6_lathe, gen_cnc8x6_mill, gen_isg_lathe, gen_isg_mill, gen_sinumerik_mill]


def grammar_line(dialect: str):
    """A one-line generator for ``mutate_lines``' insert-line: a line of a fresh grammar program."""
    gen = {"cnc8x6": [gen_cnc8x6_lathe, gen_cnc8x6_mill], "isg": [gen_isg_lathe],
           "sinumerik": [gen_sinumerik_mill]}.get(dialect, [gen_cnc8x6_lathe])

    def line(rng: random.Random) -> str:
        g = rng.choice(gen)(rng)
        ls = [ln for ln in g.program.splitlines() if ln.strip()]
        return rng.choice(ls) if ls else ""
    return line


# -------------------------------------------------------------------------------------------------
# setup mutations

def _leaves(d, path=()):
    if isinstance(d, dict):
        for k, v in d.items():
            yield from _leaves(v, path + (k,))
    elif isinstance(d, list) and d and all(isinstance(x, dict) for x in d):
        for i, v in enumerate(d):
            yield from _leaves(v, path + (i,))
    else:
        yield path, d


def _get_parent(d, path):
    for p in path[:-1]:
        d = d[p]
    return d


WEIRD_VALUES = [0, -1, 1, 2 ** 63 - 1, -(2 ** 63), 2 ** 64, 10 ** 30, 0.0, -0.0, 1e-300, 1e-9, 1e300, 1e308,
                float("inf"), float("-inf"), float("nan"), "", "x", "lathe", "mill", "cnc8x6", "1.5", True, False, [],
                [1], [1, 2], [1, 2, 3], [[0, 0]], {}, {"a": 1}, Raw("1979-05-27"), Raw("07:32:00"),
                Raw("1979-05-27T07:32:00Z"), Raw("0x10"), Raw("0o17"), Raw("0b101"), Raw("1_000"), Raw("+inf"),
                Raw("'lit'"), Raw('"""multi\nline"""'), Raw("[1, 'a', [2]]"), -5.5, 1e6, 0.001]

TOOL_ODD = {
    "diameter": [0.0, -4.0, 1e-6, 1e-3, 1e6, 0.01, 500.0, float("nan")],
    "length": [0.0, 1e-4, -1.0, 1e5, 0.5],
    "corner_radius": [0.0, 5.0, 100.0, -1.0, 1e-9, 3.0],
    "angle": [0.0, 180.0, 179.99, 360.0, -30.0, 1e-6, 0.5, 90.0, 120.0],
    "tip_radius": [0.0, 5.0, 100.0, -0.1, 1e-9, 10.0],
    "height": [0.0, 1e-4, 1e4, -1.0],
    "thickness": [0.0, 1e-6, 1e4, -1.0],
    "points": [[[0, 0], [1, 1]], [[0, 0], [1, 0], [2, 0]], [[0, 0], [1, 1], [1, 0], [0, 1]], [[0, 0]] * 3,
               [[0, 0], [1e6, 1], [-1e6, 1]], [[0, 0], [1, 2], [-1, 2], [0, 0]],
               [[math.cos(a / 100 * 2 * math.pi) * 2, 2 + math.sin(a / 100 * 2 * math.pi) * 2] for a in range(100)],
               [[0, 0], [0.001, 0.001], [-0.001, 0.001]], [[0, -1], [1, 1], [-1, 1]], [[0, 1], [1, 2], [-1, 2]]],
    "number": [0, -1, 10 ** 20, 1.5, 99999],
}

STOCK_ODD = {
    "diameter": [0.0, 1e-4, -5.0, 1e5, float("inf")],
    "z": [[0, 0], [5, 0], [-1e9, 1e9], [0, 1e-6], [float("nan"), 1], [0, float("inf")], [0], [0, 1, 2]],
    "x": [[0, 0], [10, 0], [-1e7, 1e7], [0, 1e-7], [0, float("inf")]],
    "y": [[0, 0], [10, 0], [-1e7, 1e7], [0, 1e-7]],
    "profile": [[[0, 0], [5, 0], [5, 5]], [[0, 0], [5, 5], [5, 0], [0, 5]], [[-1, 0], [5, 0], [5, 5], [-1, 5]],
                [[0, 0], [5, 0]], [[0, 0], [5, 0], [5, 0], [0, 0]], [[1, 0], [5, 0], [5, 5], [1, 5]],
                [[0, 0], [5, 0], [5, 5], [0, 5], [0, 0]], [[0, 0], [1e-9, 0], [1e-9, 1e-9], [0, 1e-9]],
                [[0, 0], [3, 0], [3, 2], [1, 2], [1, 1], [4, 1], [4, 3], [0, 3]]],
    "path": ["missing.stl", "", ".", "setup.toml", "blank.stl", "../blank.stl", "/dev/null", "/dev/zero",
             "blank.stl\u0000", "out"],
}

MACHINE_ODD = {
    "start": [[float("nan"), 0, 0], [1e300, 0, 0], [0, 0], [0, 0, 0, 0], ["a", 0, 0], [0, 0, float("inf")],
              [-1e9, 0, 1e9]],
    "rapid": [0.0, -1.0, 1e-300, float("inf"), 1e300],
    "feed": [0.0, -1.0, 1e-300, 1e300],
    "constants": [{"8": 99999999}, {"8": -99999999}, {"8": 1e30}, {"8": 0.5}, {"8": "x"}, {"08": 112500},
                  {"-1": 1}, {"8.5": 1}, {"8": 190000}, {"8": 412500}, {"8": 112500.5}, {"8": 99000000},
                  {"8": 80000000}, {"8": 123456789}, {"8": float("nan")}, {"8": 4000000, "9": 1}, {"": 1}],
}


# valid but extreme values (the documented range ends): where geometry is most fragile
TOOL_EDGE = {
    "diameter": [0.001, 0.002, 0.01, 10000.0, 9999.999, 0.5], "length": [0.001, 0.01, 10000.0, 1000.0],
    "corner_radius": [0.001, "half"], "angle": [1.0, 179.0, 1.001, 178.999, 90.0], "tip_radius": [0.001, 0.0, "max"],
    "height": [0.001, 10000.0, 0.01], "thickness": [0.001, 10000.0],
    "points": [[[0, 0], [0.001, 0.001], [-0.001, 0.001]], [[0, 0], [10000, 1], [-10000, 1]],
               [[0, 0], [1, 0.000002], [-1, 0.000002]], [[0, 0], [5, 5], [0, 10], [-5, 5]]],
}
STOCK_EDGE = {
    "diameter": [0.001, 0.002, 0.01, 1000.0], "z": [[0.0, 0.001], [-99999.0, 99999.0], [99990.0, 100000.0]],
    "x": [[0.0, 0.001], [-100000.0, 100000.0]], "y": [[0.0, 0.001], [-100000.0, 100000.0]],
}


def edge_setup(rng: random.Random, setup: dict) -> list[str]:
    """Valid values at the ends of the documented ranges (tools, stock, tolerance)."""
    notes = []
    tools = setup.get("tool")
    if isinstance(tools, list) and tools and rng.random() < 0.7:
        t = rng.choice(tools)
        keys = [k for k in TOOL_EDGE if k in t or rng.random() < 0.2]
        if keys:
            k = rng.choice(keys)
            v = rng.choice(TOOL_EDGE[k])
            if v == "half":
                v = float(t.get("diameter", 4.0)) / 2
            if v == "max":  # the largest nose radius the height allows: r (1 - sin(a/2)) < h
                a, h = float(t.get("angle", 60.0)), float(t.get("height", 10.0))
                v = round(h / (1 - math.sin(math.radians(a / 2))) * 0.999, 3)
            t[k] = v
            notes.append(f"edge tool.{k} = {v}")
    st = setup.get("stock")
    if isinstance(st, dict) and rng.random() < 0.5:
        k = rng.choice([k for k in STOCK_EDGE if k in st] or ["z"])
        st[k] = rng.choice(STOCK_EDGE[k])
        notes.append(f"edge stock.{k} = {st[k]}")
    return notes


def mutate_setup(rng: random.Random, setup: dict, machine: str) -> list[str]:
    """Structured mutations of a setup dict in place; returns notes."""
    notes = []
    if rng.random() < 0.3:
        return edge_setup(rng, setup)
    for _ in range(rng.choice([1, 1, 1, 2, 3])):
        c = rng.random()
        leaves = [(p, v) for p, v in _leaves(setup) if p]
        if c < 0.25 and leaves:
            p, v = rng.choice(leaves)
            nv = rng.choice(WEIRD_VALUES)
            _get_parent(setup, p)[p[-1]] = nv
            notes.append(f"{'.'.join(map(str, p))} = {toml_value(nv)}")
        elif c < 0.45:
            tools = setup.get("tool")
            if isinstance(tools, list) and tools and isinstance(tools[0], dict):
                t = rng.choice(tools)
                k = rng.choice(list(TOOL_ODD))
                t[k] = rng.choice(TOOL_ODD[k])
                notes.append(f"tool.{k} = {toml_value(t[k])}")
        elif c < 0.58:
            st = setup.get("stock")
            if isinstance(st, dict):
                k = rng.choice(list(STOCK_ODD))
                st[k] = rng.choice(STOCK_ODD[k])
                if rng.random() < 0.4:
                    st["shape"] = {"diameter": "cylinder", "z": st.get("shape", "cylinder"), "x": "box", "y": "box",
                                   "profile": "revolve", "path": "mesh"}[k]
                notes.append(f"stock.{k} = {toml_value(st[k])}")
        elif c < 0.68:
            m = setup.get("machine")
            if isinstance(m, dict):
                k = rng.choice(list(MACHINE_ODD) + ["kind", "dialect", "diameter_programming", "m03"])
                m[k] = rng.choice(MACHINE_ODD.get(k, ["lathe", "mill", "isg", "sinumerik", "cnc8x6", "positive",
                                                       "negative", True, False, "", "LATHE", 1]))
                notes.append(f"machine.{k} = {toml_value(m[k])}")
        elif c < 0.76 and leaves:
            p, _ = rng.choice(leaves)
            del _get_parent(setup, p)[p[-1]]
            notes.append(f"delete {'.'.join(map(str, p))}")
        elif c < 0.82:
            tab = rng.choice(list(setup)) if setup else "machine"
            del_tab = rng.random() < 0.4
            if del_tab:
                setup.pop(tab, None)
                notes.append(f"delete [{tab}]")
            else:
                key = rng.choice(["colour", "Kind", "kind ", "tolerance", "8", "R04", "unknown", "diameter"])
                if isinstance(setup.get(tab), dict):
                    setup[tab][key] = rng.choice([1, "x", True])
                elif isinstance(setup.get(tab), list) and setup[tab] and isinstance(setup[tab][0], dict):
                    setup[tab][0][key] = 1
                notes.append(f"extra key {tab}.{key}")
        elif c < 0.88:
            sim = setup.setdefault("simulation", {}) if isinstance(setup.get("simulation", {}), dict) else {}
            k = rng.choice(["tolerance", "max_blocks", "fail_on_warning"])
            sim[k] = rng.choice({"tolerance": [0.0, 1e-5, 1e-4, 1.0, 1.0001, -0.05, float("nan"), 2, True, "0.05"],
                                 "max_blocks": [0, 1, 2, 5, -1, 1.5, 2 ** 70, 10 ** 9, "5"],
                                 "fail_on_warning": [True, False, 1, "yes"]}[k])
            notes.append(f"simulation.{k} = {toml_value(sim[k])}")
        elif c < 0.93:
            params = setup.setdefault("parameters", {}) if isinstance(setup.get("parameters", {}), dict) else {}
            k = rng.choice(["R04", "R0", "R00", "R80", "R1000", "R-1", "r4", "R4.5", "R 4", "R99", "R15", "R16"])
            params[k] = rng.choice([120.0, -120.0, 1e300, float("nan"), float("inf"), "x", 0, 2 ** 64, 99999999.0])
            notes.append(f"parameters.{k} = {toml_value(params[k])}")
        elif c < 0.97:
            kind = machine
            bbox = (-10, 10, -10, 10, -5, 0)
            chk = random_check(rng, kind if rng.random() < 0.8 else ("mill" if kind == "lathe" else "lathe"), bbox)
            if rng.random() < 0.3 and chk:
                k = rng.choice(list(chk))
                chk[k] = rng.choice(WEIRD_VALUES)
            setup.setdefault("check", []) if isinstance(setup.get("check", []), list) else None
            if isinstance(setup.get("check", []), list):
                setup.setdefault("check", []).append(chk)
            notes.append(f"check {toml_value(chk)}")
        else:
            tools = setup.get("tool")
            if isinstance(tools, list):
                if tools and rng.random() < 0.5:
                    tools.append(dict(tools[0]))
                    notes.append("duplicate tool")
                else:
                    setup["tool"] = {"kind": "endmill", "diameter": 4.0}
                    notes.append("tool as a table")
    return notes


# -------------------------------------------------------------------------------------------------
# command lines

TOLERANCES = ["0.05", "0.05", "0.1", "0.02", "0", "-0.05", "nan", "inf", "-inf", "1e-6", "2", "1", "1.0000001",
              "abc", "", "0x1", "1e-5", "1e-4", "1e400", "0.05 ", " 0.05", "0,05", "\u0660.\u0660\u0665"]
FORMATS = ["stl", "stl", "3mf", "glb", "STL", "obj", ""]


def base_argv(program: str, tol: str = "0.05") -> list[str]:
    return ["simulate", program, "--setup", "setup.toml", "--out", "out", "--tolerance", tol, "-q"]


def mutate_cli(rng: random.Random, case: Case) -> None:
    prog = case.argv[1]
    c = rng.random()
    if c < 0.3:
        tol = rng.choice(TOLERANCES)
        if tol in ("1e-4", "1e-5", "1e-6") and case.size() > 600:
            tol = "0.05"
        case.argv[case.argv.index("--tolerance") + 1] = tol
        case.notes.append(f"--tolerance {tol!r}")
    elif c < 0.45:
        f = rng.choice(FORMATS)
        case.argv += ["--format", f]
        case.fmt = f
        case.notes.append(f"--format {f!r}")
    elif c < 0.62:
        o = rng.choice(["out/a/b/c", "out dir", "\u00fcber", "prog_out", "setup.toml", "out/", "./out", "a/../out",
                        "existing", "existing-file", "", "/dev/null", "out" + "x" * 300])
        i = case.argv.index("--out") + 1
        case.argv[i] = o
        case.out = o
        if o == "existing":
            case.files["existing/keep.txt"] = b"keep me\n"
        if o == "existing-file":
            case.files["existing-file"] = b"not a directory\n"
        case.notes.append(f"--out {o!r}")
    elif c < 0.72:
        what = rng.choice(["program", "setup", "both"])
        if what in ("program", "both"):
            alt = rng.choice(["missing.nc", "setup.toml", ".", "sub", "/dev/null", "prog\u00e4.nc"])
            case.argv[1] = alt
            if alt == "sub":
                case.files["sub/x.txt"] = b"x\n"
            if alt == "prog\u00e4.nc":
                case.files[alt] = case.files[prog]
            if alt == "missing.nc":
                case.missing = case.missing + ("missing.nc",)
        if what in ("setup", "both"):
            alt = rng.choice(["missing.toml", prog, ".", "/dev/null"])
            case.argv[case.argv.index("--setup") + 1] = alt
            if alt == "missing.toml":
                case.missing = case.missing + ("missing.toml",)
        case.notes.append(f"swap files: {what}")
    elif c < 0.8:
        case.argv.remove("-q")
        case.notes.append("not quiet (progress and summary)")
    elif c < 0.86:
        case.argv = ["moves", prog, "--setup", "setup.toml"]
        case.out = None
        case.notes.append("moves")
    elif c < 0.9:
        drop = rng.choice(["--setup", "--out"])
        i = case.argv.index(drop)
        del case.argv[i:i + 2]
        case.out = None if drop == "--out" else case.out
        case.notes.append(f"without {drop}")
    elif c < 0.94:
        extra = rng.choice([["--tolerance", "0.1"], ["--bogus"], ["--out", "out2"], ["-h"], ["--version"], ["x"],
                            ["--quiet"], ["--format"], ["--setup"]])
        case.argv += extra
        if extra == ["--out", "out2"]:
            case.out = "out2"
        case.notes.append(f"extra args {extra}")
    else:
        case.argv = rng.choice([["simulate"], [], ["simulate", "--help"], ["moves"], ["bogus"], ["simulate", prog]])
        case.out = None
        case.notes.append(f"argv {case.argv}")


# -------------------------------------------------------------------------------------------------
# making cases

KIND_WEIGHTS = [("example", 30), ("grammar", 42), ("setup", 16), ("cli", 12)]


def _pick_kind(rng: random.Random) -> str:
    tot = sum(w for _, w in KIND_WEIGHTS)
    x = rng.uniform(0, tot)
    for k, w in KIND_WEIGHTS:
        x -= w
        if x <= 0:
            return k
    return KIND_WEIGHTS[-1][0]


def _from_gen(index: int, kind: str, g: Gen, rng: random.Random, mutate_setup_text: bool = False) -> Case:
    setup_text = toml_dump(g.setup, rng if rng.random() < 0.3 else None)
    files = {g.program_name: g.program.encode("utf-8"), "setup.toml": setup_text.encode("utf-8")}
    files.update(g.extra)
    tol = rng.choice(["0.05", "0.05", "0.05", "0.1", "0.2"])
    return Case(index, kind, g.dialect, files, base_argv(g.program_name, tol), [f"{g.dialect}-{g.machine}"])


def _shrink_lathe_setup(text: str, rng: random.Random) -> tuple[str, str | None]:
    """Clip a long cylinder's z range to its top 12 mm (the same programs, a fraction of the cost)."""
    m = re.search(r"(?m)^z\s*=\s*\[\s*(-?[\d.]+)\s*,\s*(-?[\d.]+)\s*\]", text)
    if m and "cylinder" in text:
        lo, hi = float(m.group(1)), float(m.group(2))
        if hi - lo > 20:
            return text[:m.start()] + f"z = [{hi - 12}, {hi}]" + text[m.end():], f"stock z clipped to [{hi - 12}, {hi}]"
    return text, None


def make_case(seed: int, index: int, seeds: list[Seed] | None = None) -> Case:
    """Case ``index`` of run ``seed`` (deterministic for a fixed set of example files)."""
    rng = random.Random(f"cutsim-fuzz:{seed}:{index}")
    kind = _pick_kind(rng)
    seeds = corpus() if seeds is None else seeds
    if kind == "example" and seeds:
        s = rng.choice(seeds)
        if b'"design"' in s.setup and rng.random() < 0.8:  # design checks cost seconds: fewer of them
            s = rng.choice(seeds)
        prog, notes, line = mutate_program(rng, s.program.decode("utf-8", "replace"), s.dialect, grammar_line(s.dialect))
        setup = s.setup.decode("utf-8", "replace")
        if rng.random() < 0.7:
            setup, note = _shrink_lathe_setup(setup, rng)
            if note:
                notes.append(note)
        if rng.random() < 0.5 and "max_blocks" not in setup:
            setup += "\n[simulation]\nmax_blocks = 20000\n" if "[simulation]" not in setup else ""
        files = {s.program_name: prog, "setup.toml": setup.encode("utf-8")}
        for k, v in s.extra.items():
            files.setdefault(k, v)
        tol = rng.choice(["0.05", "0.1", "0.2"])
        case = Case(index, "example", s.dialect, files, base_argv(s.program_name, tol), [s.label] + notes)
        if line is not None and s.valid:
            case.expect_line = (s.program_name, line)
        return case
    gen = rng.choice(GENERATORS)
    g = gen(rng)
    if kind == "grammar":
        case = _from_gen(index, kind, g, rng)
        if rng.random() < 0.3:  # grammar program, lightly mutated
            prog, notes, line = mutate_program(rng, g.program, g.dialect, grammar_line(g.dialect))
            case.files[g.program_name] = prog
            case.notes += notes  # no injected-error oracle: the grammar program itself may be wrong
        return case
    if kind == "setup":
        notes = []
        if rng.random() < 0.35 and seeds:  # a shipped example's setup, mutated (its program unchanged)
            s = rng.choice(seeds)
            try:
                data = tomllib.loads(s.setup.decode("utf-8"))
            except Exception:  # noqa: BLE001
                data = {}
            if data:
                notes = [s.label] + mutate_setup(rng, data, s.kind)
                files = {s.program_name: s.program, "setup.toml": toml_dump(data, rng if rng.random() < 0.3 else None)
                         .encode("utf-8")}
                for k, v in s.extra.items():
                    files.setdefault(k, v)
                return Case(index, "setup", s.dialect, files, base_argv(s.program_name, rng.choice(["0.05", "0.1"])),
                            notes)
        if rng.random() < 0.75:
            notes = mutate_setup(rng, g.setup, g.machine)
            case = _from_gen(index, kind, g, rng)
        else:  # text-level: line and byte mutations of the TOML
            case = _from_gen(index, kind, g, rng)
            lines = _split(case.files["setup.toml"].decode("utf-8"))

            def tok(r):
                return r.choice(["[machine]", "[[tool]]", "[stock]", "kind = ", "= 1", "x = [1, 2", '"unterminated',
                                 "a.b.c = 1", "[machine.constants]", "8 = 112500", "[simulation]", "dialect = 'isg'",
                                 "\\u12", "key = \"\\q\"", "tolerance = 0.05", "[tool]", "[[machine]]", "]]", "#"])
            for _ in range(rng.choice([1, 1, 2, 3])):
                notes.append("setup " + mutate_lines(rng, lines, tok))
            data = "\n".join(lines).encode("utf-8")
            if rng.random() < 0.3:
                data, note = mutate_bytes(rng, data)
                notes.append("setup " + note)
            case.files["setup.toml"] = data
        case.notes += notes
        if "blank.stl" not in case.files and b"blank.stl" in case.files["setup.toml"]:
            data, note = random_mesh_file(rng, (-10, 10, -10, 10, -5, 0))
            case.files["blank.stl"] = data
            case.notes.append(f"blank.stl: {note}")
        return case
    case = _from_gen(index, "cli", g, rng)
    mutate_cli(rng, case)
    return case


# -------------------------------------------------------------------------------------------------
# running: persistent forked workers

def warm_imports() -> None:
    """Import what a run needs once in the parent, so forked workers start warm."""
    for k, v in (("OMP_NUM_THREADS", "1"), ("OPENBLAS_NUM_THREADS", "1"), ("MKL_NUM_THREADS", "1")):
        os.environ.setdefault(k, v)
    import click  # noqa: F401
    import numpy  # noqa: F401
    import trimesh  # noqa: F401

    import cutsim  # noqa: F401
    import cutsim.cli  # noqa: F401
    try:
        import cutsim.kinematics  # noqa: F401
        import cutsim.reports.report  # noqa: F401
        import cutsim.stock  # noqa: F401
    except Exception:  # noqa: BLE001 - a half-edited module elsewhere shows up as case results
        pass


_LOC = re.compile(r"^(?P<file>.+?):(?P<line>-?\d+):(?P<col>-?\d+): error: (?P<msg>.*)$", re.M)


def _editor_lines(raw: bytes) -> int:
    """Lines an editor shows: LF, CR LF and CR end lines; the position after a final line end counts."""
    return raw.count(b"\n") + raw.count(b"\r") - raw.count(b"\r\n") + 1


def _editor_line_bytes(raw: bytes, n: int) -> bytes:
    lines = raw.replace(b"\r\n", b"\n").replace(b"\r", b"\n").split(b"\n")
    return lines[n - 1] if 1 <= n <= len(lines) else b""


def check_location(stderr: str, casedir: str, case: dict) -> tuple[str, str]:
    """(class, detail) for an exit-2 result."""
    if re.search(r"^(Usage:|Error: )", stderr, re.M) and not _LOC.search(stderr):
        return "usage", stderr.strip().splitlines()[-1][:200] if stderr.strip() else ""
    m = _LOC.search(stderr)
    if not m:
        return "bad-location", "no FILE:LINE:COL: error: line: " + stderr.strip()[:200]
    f, line, col, msg = m.group("file"), int(m.group("line")), int(m.group("col")), m.group("msg")
    if msg.startswith("--") or (f == "cutsim" and line == 0):
        return "usage", msg[:200]  # a command-line option, reported as cutsim:0:0 or OUT:0:0
    path = f if os.path.isabs(f) else os.path.join(casedir, f)
    if os.path.exists(path) and not os.path.isfile(path) and line == 0:
        return "ok-exit2", ""  # a directory or device named where a file belongs: the whole "file"
    if not os.path.isfile(path):
        if os.path.basename(f) in case.get("missing", ()) or f in case.get("missing", ()):
            return "ok-exit2", ""
        if not os.path.exists(path) and (f in case.get("argv", ()) or "cannot read" in msg):
            return "ok-exit2", ""  # the command line named a directory or device
        return "bad-location", f"names a file that does not exist: {f}:{line}:{col}: {msg[:160]}"
    raw = open(path, "rb").read()
    n = _editor_lines(raw)
    if not 1 <= line <= n:
        return "bad-location", f"line {line} of {os.path.basename(f)} ({n} lines): {msg[:200]}"
    exp = case.get("expect_line")
    if exp and os.path.basename(f) == exp[0] and line != exp[1]:
        return "wrong-line", f"line {line} instead of {exp[1]} (the injected error): {msg[:200]}"
    width = len(_editor_line_bytes(raw, line))
    if col < 0 or col > width + 2:
        return "bad-location", f"column {col} of line {line} ({width} bytes): {msg[:200]}"
    return "ok-exit2", ""


def check_part(casedir: str, case: dict) -> tuple[str, str]:
    out, fmt = case.get("out"), (case.get("fmt") or "stl").lower()
    argv = case.get("argv", ())
    if out is None or "simulate" not in argv[:1] or {"-h", "--help", "--version"} & set(argv):
        return "", ""
    if fmt not in ("stl", "3mf", "glb"):
        return "", ""
    path = os.path.normpath(os.path.join(casedir, out, f"part.{fmt}"))  # "a/../out" is "out" for cutsim
    if not os.path.isfile(path):
        return "missing-part", f"no {out}/part.{fmt}"
    import trimesh

    try:
        mesh = trimesh.load(path, force="mesh")
    except Exception as e:  # noqa: BLE001
        if os.path.getsize(path) <= 84 and fmt == "stl":
            return "", "empty part"
        return "leaky-part", f"unreadable part: {type(e).__name__}: {e}"[:200]
    rep = os.path.join(os.path.dirname(path), "report.json")
    try:
        import json

        with open(rep, "rb") as f:
            r = json.load(f)
        missing = [k for k in ("program", "dialect", "blocks", "moves", "part_volume", "warnings") if k not in r]
        if missing:
            return "missing-part", f"report.json lacks {missing}"
    except (OSError, ValueError) as e:
        return "missing-part", f"report.json: {type(e).__name__}"
    if len(mesh.faces) == 0:
        return "", "empty part"
    if not (mesh.is_watertight and mesh.is_volume):
        return "leaky-part", (f"watertight={mesh.is_watertight} volume={mesh.is_volume} faces={len(mesh.faces)} "
                              f"winding={mesh.is_winding_consistent}")
    return "", ""


def _written(casedir: str, case: dict) -> list[str]:
    out = case.get("out")
    if not out:
        return []
    before = set(case.get("preexisting", ()))
    d = os.path.normpath(os.path.join(casedir, out))
    if not os.path.isdir(d) or not d.startswith(os.path.normpath(casedir)):
        return []
    found = []
    for root, _, names in os.walk(d):
        for nm in names:
            rel = os.path.relpath(os.path.join(root, nm), casedir)
            if rel not in before and nm not in (".stderr", ".stdout"):
                found.append(rel)
    return found


def classify(code: int, stderr: str, casedir: str, case: dict) -> tuple[str, str]:
    if "Traceback (most recent call last)" in stderr:
        return "traceback", _trace_signature(stderr)
    if code == 3:
        if re.search(r"MemoryError|Unable to allocate|bad_alloc|std::bad", stderr):
            return "memory", _first_error(stderr)
        return "exit3", _first_error(stderr)
    if code == 2:
        cls, det = check_location(stderr, casedir, case)
        if cls in ("ok-exit2", "usage"):
            w = _written(casedir, case)
            if w:
                return "partial-output", f"exit 2 but wrote {sorted(w)[:4]}: {_first_error(stderr)}"
        return cls, det
    if code in (0, 1):
        cls, det = check_part(casedir, case)
        if cls:
            return cls, det
        return ("ok-exit0" if code == 0 else "exit1"), det
    return "other-exit", f"exit status {code}: {_first_error(stderr)}"


def _first_error(stderr: str) -> str:
    for ln in stderr.splitlines():
        if "error" in ln.lower() or "Error" in ln:
            return ln[:300]
    return stderr.strip()[:300]


def _trace_signature(text: str) -> str:
    frames = re.findall(r'File "([^"]+)", line (\d+), in (\S+)', text)
    last = ""
    for f, ln, fn in frames:
        if "cutsim" in f or "/work/main" in f or "site-packages/click" in f:
            last = f"{os.path.basename(f)}:{fn}"
    exc = ""
    for ln in reversed(text.strip().splitlines()):
        if re.match(r"^[A-Za-z_][\w.]*(Error|Exception|Exit|Interrupt|Warning)?\b.*", ln) and not ln.startswith(" "):
            exc = ln.split(":")[0]
            break
    return f"{exc} at {last}"


class _Worker:
    def __init__(self, ctx, mem_mib: int, tmp: str):
        self.parent, child = ctx.Pipe()
        self.proc = ctx.Process(target=_worker_main, args=(child, mem_mib, tmp), daemon=True)
        self.proc.start()
        child.close()
        self.case: dict | None = None
        self.t0 = 0.0
        self.done = 0
        self.phase = "run"
        self.result: dict | None = None
        self.cpu0 = 0.0

    def kill(self) -> None:
        try:
            self.proc.kill()
        except Exception:  # noqa: BLE001
            pass
        self.proc.join(5)
        self.parent.close()


def _worker_main(conn, mem_mib: int, tmp: str) -> None:
    try:
        set_limits(mem_mib)  # the limits of a batch job (cutsim.batch.process)
    except (ValueError, OSError):
        pass
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    # fresh text streams on fds 1 and 2 (pytest's capture replaces sys.stderr with its own file)
    sys.stdout = open(1, "w", encoding="utf-8", errors="backslashreplace", closefd=False)
    sys.stderr = open(2, "w", encoding="utf-8", errors="backslashreplace", closefd=False)
    faulthandler.register(signal.SIGUSR1, file=sys.stderr, all_threads=True)
    fd1, fd2 = os.dup(1), os.dup(2)
    while True:
        try:
            msg = conn.recv()
        except (EOFError, OSError):
            return
        if msg is None:
            return
        case, casedir = msg
        res = _run_inproc(case, casedir, fd1, fd2)
        conn.send(("result", res))
        trace = None
        if res["cls"] in ("exit3", "memory") and case["argv"][:1] == ["simulate"]:
            trace = _api_trace(case, casedir, fd1, fd2)
        conn.send(("trace", trace))


def _redirect(casedir: str):
    sys.stdout.flush()
    sys.stderr.flush()
    err = open(os.path.join(casedir, ".stderr"), "w+b", buffering=0)
    out = open(os.path.join(casedir, ".stdout"), "w+b", buffering=0)
    os.dup2(err.fileno(), 2)
    os.dup2(out.fileno(), 1)
    return err, out


def _restore(fd1: int, fd2: int, err, out) -> str:
    try:
        sys.stdout.flush()
        sys.stderr.flush()
    except Exception:  # noqa: BLE001
        pass
    os.dup2(fd1, 1)
    os.dup2(fd2, 2)
    err.seek(0)
    text = err.read().decode("utf-8", "replace")
    err.close()
    out.close()
    return text


def _run_inproc(case: dict, casedir: str, fd1: int, fd2: int) -> dict:
    os.chdir(casedir)
    err, out = _redirect(casedir)
    t0 = time.monotonic()
    ru0 = resource.getrusage(resource.RUSAGE_SELF)
    code = 0
    try:
        from cutsim.cli import main

        main.main(args=list(case["argv"]), prog_name="cutsim", standalone_mode=True)
    except SystemExit as e:
        if e.code is None:
            code = 0
        elif isinstance(e.code, int):
            code = e.code
        else:
            print(e.code, file=sys.stderr)
            code = 1
    except MemoryError:
        traceback.print_exc()
        code = 1
    except BaseException:  # noqa: BLE001 - what Python would print for an uncaught exception
        traceback.print_exc()
        code = 1
    dt = time.monotonic() - t0
    ru1 = resource.getrusage(resource.RUSAGE_SELF)
    cpu = ru1.ru_utime + ru1.ru_stime - ru0.ru_utime - ru0.ru_stime
    stderr = _restore(fd1, fd2, err, out)
    tc = time.process_time()
    try:
        cls, detail = classify(code, stderr, casedir, case)
    except MemoryError:
        cls, detail = "ok-exit0" if code == 0 else "exit1", "part too large to check"
    except Exception as e:  # noqa: BLE001 - a checker bug must not look like a cutsim bug
        cls, detail = "other-exit", f"fuzz checker failed: {type(e).__name__}: {e}"
    os.chdir(os.path.dirname(casedir))
    return {"code": code, "stderr": stderr[-20000:], "time": dt, "cpu": cpu, "check_cpu": time.process_time() - tc,
            "cls": cls, "detail": detail}


def _api_trace(case: dict, casedir: str, fd1: int, fd2: int) -> str | None:
    """The traceback of an internal error: the same run through ``cutsim.simulate`` (the CLI hides it)."""
    argv = case["argv"]
    try:
        prog = argv[1]
        setup = argv[argv.index("--setup") + 1]
        tol = float(argv[argv.index("--tolerance") + 1]) if "--tolerance" in argv else None
    except (ValueError, IndexError):
        return None
    os.chdir(casedir)
    err, out = _redirect(casedir)
    tb = None
    try:
        import cutsim
        from cutsim.reports.report import mesh_arrays, part_bytes, report_bytes

        r = cutsim.simulate(prog, setup, tolerance=tol)
        v, f = mesh_arrays(r.part)
        part_bytes(v, f, case.get("fmt") or "stl")
        report_bytes(r.report)
    except BaseException as e:  # noqa: BLE001
        if type(e).__name__ != "CutsimError":
            tb = traceback.format_exc()
    _restore(fd1, fd2, err, out)
    os.chdir(os.path.dirname(casedir))
    return tb[-6000:] if tb else None


def features(c: Case) -> str:
    """A coarse description of a case for grouping results without a traceback (leaky parts):
    machine kind, stock shape, tool kinds."""
    try:
        data = tomllib.loads(c.files.get("setup.toml", b"").decode("utf-8"))
        kind = data.get("machine", {}).get("kind", "?")
        shape = data.get("stock", {}).get("shape", "?")
        tools = sorted({str(t.get("kind", "?")) + ("(corner)" if t.get("corner_radius") else "")
                        for t in data.get("tool", []) if isinstance(t, dict)})
        return f"{kind}/{shape}/{'+'.join(tools)}"
    except Exception:  # noqa: BLE001
        return "?"


def _case_dict(c: Case) -> dict:
    return {"index": c.index, "argv": list(c.argv), "out": c.out, "fmt": c.fmt, "expect_line": c.expect_line,
            "missing": list(c.missing), "preexisting": [k for k in c.files]}


def write_case_files(c: Case, d: str) -> None:
    os.makedirs(d, exist_ok=True)
    for name, data in c.files.items():
        p = os.path.join(d, name)
        os.makedirs(os.path.dirname(p), exist_ok=True)
        with open(p, "wb") as f:
            f.write(data)


class Runner:
    """Runs cases on ``jobs`` persistent forked workers. ``run`` yields ``(case, result)`` in
    completion order; ``result``: code, stderr, time, cls, detail, trace (internal errors), stack (hangs)."""

    def __init__(self, jobs: int = 1, timeout: float = 30.0, mem_mb: int = 3072, tmp: str | None = None,
                 recycle: int = 300, trace_timeout: float | None = None):
        import multiprocessing
        import tempfile

        warm_imports()
        self.ctx = multiprocessing.get_context("fork")
        self.jobs, self.timeout, self.mem = jobs, timeout, mem_mb
        self.trace_timeout = trace_timeout if trace_timeout is not None else max(5.0, timeout / 2)
        self.tmp = tmp or tempfile.mkdtemp(prefix="cutsim-fuzz-")
        os.makedirs(self.tmp, exist_ok=True)
        self.recycle = recycle
        self.workers: list[_Worker] = []
        self._own_tmp = tmp is None

    def _new(self) -> _Worker:
        return _Worker(self.ctx, self.mem, self.tmp)

    def close(self) -> None:
        for w in self.workers:
            try:
                w.parent.send(None)
            except Exception:  # noqa: BLE001
                pass
            w.proc.join(2)
            if w.proc.is_alive():
                w.kill()
        self.workers = []
        if self._own_tmp:
            shutil.rmtree(self.tmp, ignore_errors=True)

    def run(self, cases):
        from multiprocessing.connection import wait

        it = iter(cases)
        pending = True
        if not self.workers:
            self.workers = [self._new() for _ in range(self.jobs)]
        busy: dict[int, tuple[_Worker, Case, str]] = {}
        try:
            while True:
                for slot, w in enumerate(self.workers):
                    if slot in busy or not pending:
                        continue
                    try:
                        c = next(it)
                    except StopIteration:
                        pending = False
                        break
                    if w.done >= self.recycle or not w.proc.is_alive():
                        w.kill()
                        w = self.workers[slot] = self._new()
                    d = os.path.join(self.tmp, f"case{c.index}")
                    shutil.rmtree(d, ignore_errors=True)
                    write_case_files(c, d)
                    w.case, w.t0, w.phase, w.result = _case_dict(c), time.monotonic(), "run", None
                    w.cpu0 = cpu_seconds(w.proc.pid)
                    w.parent.send((w.case, d))
                    busy[slot] = (w, c, d)
                if not busy:
                    return
                now = time.monotonic()
                deadline = min(w.t0 + (self.timeout if w.phase == "run" else self.trace_timeout)
                               for w, _, _ in busy.values())
                ready = wait([w.parent for w, _, _ in busy.values()], timeout=max(0.0, deadline - now))
                for slot in list(busy):
                    w, c, d = busy[slot]
                    finished = None
                    if w.parent in ready:
                        try:
                            kind, payload = w.parent.recv()
                        except (EOFError, OSError):
                            w.proc.join(2)
                            ec = w.proc.exitcode
                            if w.phase == "run":
                                sig = -ec if ec is not None and ec < 0 else None
                                err = _read(os.path.join(d, ".stderr"))
                                cls = "memory" if sig == signal.SIGKILL else "segfault"
                                finished = {"code": ec, "stderr": err[-20000:], "time": time.monotonic() - w.t0,
                                            "cls": cls, "detail": f"worker died: exit {ec}"
                                            + (f" (signal {signal.Signals(sig).name})" if sig else "")}
                            else:
                                finished = w.result
                                finished["trace"] = "worker died while tracing"
                            w.kill()
                            self.workers[slot] = self._new()
                        else:
                            if kind == "result":
                                w.result, w.phase, w.t0 = payload, "trace", time.monotonic()
                            else:
                                finished = w.result
                                finished["trace"] = payload
                                if payload:
                                    finished["detail"] = (finished["detail"] + " | " + _trace_signature(payload))
                                w.done += 1
                    elif time.monotonic() >= w.t0 + (self.timeout if w.phase == "run" else self.trace_timeout):
                        wall = time.monotonic() - w.t0
                        cpu = cpu_seconds(w.proc.pid) - w.cpu0
                        if w.phase == "run" and cpu < 0.9 * self.timeout and wall < 4 * self.timeout:
                            w.t0 += min(self.timeout - cpu, 5.0)  # a loaded machine: wait for CPU time, not wall time
                            continue
                        if w.phase == "run":
                            try:
                                os.kill(w.proc.pid, signal.SIGUSR1)
                            except OSError:
                                pass
                            time.sleep(0.3)
                            err = _read(os.path.join(d, ".stderr"))
                            finished = {"code": None, "stderr": err[-20000:], "time": wall, "cpu": round(cpu, 1),
                                        "cls": "hang", "detail": _hang_signature(err)}
                        else:
                            finished = w.result
                            finished["trace"] = "tracing timed out"
                        w.kill()
                        self.workers[slot] = self._new()
                    if finished is not None:
                        if finished["cls"] in ("leaky-part", "missing-part"):
                            finished["features"] = features(c)
                        del busy[slot]
                        shutil.rmtree(d, ignore_errors=True)
                        yield c, finished
        finally:
            for slot, (w, c, d) in list(busy.items()):
                w.kill()
                self.workers[slot] = self._new()
                shutil.rmtree(d, ignore_errors=True)


def _read(p: str) -> str:
    try:
        with open(p, "rb") as f:
            return f.read().decode("utf-8", "replace")
    except OSError:
        return ""


def _hang_signature(dump: str) -> str:
    """The innermost cutsim frames of a faulthandler dump (the main thread's stack)."""
    blk = dump.split("Current thread")[-1] if "Current thread" in dump else dump
    frames = re.findall(r'File "([^"]+)", line (\d+) in (\S+)', blk)
    ours = [f"{os.path.basename(f)}:{fn}" for f, _, fn in frames
            if "/work/main" in f or "/cutsim/" in f or os.sep + "interp" + os.sep in f or os.sep + "stock" + os.sep in f]
    return "stack: " + " <- ".join(ours[:4]) if ours else "no cutsim frames in the dump"


# -------------------------------------------------------------------------------------------------
# grouping and reproducers

def signature(cls: str, res: dict) -> str:
    det = res.get("detail", "")
    if cls in ("exit3", "memory"):
        m = re.search(r"internal error in cutsim \((\w+): (.*?)\); please", det)
        base = f"{m.group(1)}: {m.group(2)}" if m else det
        tr = det.split(" | ")[-1] if " | " in det else ""
        return f"{cls}: {_norm(base)[:120]}" + (f" [{tr}]" if tr else "")
    if cls == "traceback":
        return f"traceback: {det}"
    if cls == "hang":
        return f"hang: {det}"
    if cls in ("bad-location", "wrong-line"):
        m = re.search(r": (.*)$", det)
        return f"{cls}: {_norm(det.split(':')[0])}: {_norm(m.group(1))[:90] if m else ''}"
    if cls == "partial-output":
        return "partial-output"
    if cls in ("leaky-part", "missing-part"):
        return f"{cls}: {res.get('features', '')} {_norm(det)[:40]}"
    return f"{cls}: {_norm(det)[:100]}"


def _norm(s: str) -> str:
    s = re.sub(r"/[^\s:'\"]+/", "", s)
    s = re.sub(r"'[^']*'", "'…'", s)
    s = re.sub(r"-?\d+(\.\d+)?(e[+-]?\d+)?", "#", s)
    return s.strip()


def write_reproducer(case: Case, res: dict, d: str) -> None:
    write_case_files(case, d)
    with open(os.path.join(d, "cmd.sh"), "w") as f:
        f.write(f"#!/bin/sh\n# case {case.index} ({case.kind}, {case.dialect}): {'; '.join(case.notes)[:500]}\n"
                f"# class {res['cls']}: {res.get('detail', '')[:300]}\ncd \"$(dirname \"$0\")\" && {case.command()}\n")
    with open(os.path.join(d, "stderr.txt"), "w") as f:
        f.write(res.get("stderr", ""))
        if res.get("trace"):
            f.write("\n--- traceback through cutsim.simulate ---\n" + str(res["trace"]))


def describe(case: Case, res: dict, limit: int = 1500) -> str:
    """A reproducer as text: command, notes, short files, the first stderr lines."""
    parts = [f"case {case.index} [{res['cls']}] {res.get('detail', '')}",
             f"  notes: {'; '.join(case.notes)[:300]}", f"  $ {case.command()}"]
    for name, data in case.files.items():
        txt = data[:limit].decode("utf-8", "backslashreplace")
        parts.append(f"  --- {name} ({len(data)} bytes)\n" + "\n".join("    " + ln for ln in txt.splitlines()))
    parts.append("  --- stderr\n" + "\n".join("    " + ln for ln in res.get("stderr", "").strip().splitlines()[:8]))
    if res.get("trace"):
        parts.append("  --- traceback\n" + "\n".join("    " + ln for ln in str(res["trace"]).splitlines()[-8:]))
    return "\n".join(parts)


def minimize(runner: Runner, case: Case, cls: str, sig: str, budget: int = 150) -> Case:
    """Line-level delta debugging of the program and then the setup, keeping class and signature."""
    import copy

    runs = [0]

    def same(c: Case) -> bool:
        if runs[0] >= budget:
            return False
        runs[0] += 1
        for _, r in runner.run([c]):
            return r["cls"] == cls and signature(cls, r) == sig
        return False

    best = copy.deepcopy(case)
    for name in [n for n in (best.program, "setup.toml") if n and n in best.files]:
        raw = best.files[name]
        lines = raw.split(b"\n")
        n = 2
        while len(lines) >= 2 and runs[0] < budget:
            chunk = max(1, len(lines) // n)
            reduced = False
            for i in range(0, len(lines), chunk):
                trial = lines[:i] + lines[i + chunk:]
                c = copy.deepcopy(best)
                c.files[name] = b"\n".join(trial)
                if same(c):
                    lines, best, reduced = trial, c, True
                    n = max(n - 1, 2)
                    break
            if not reduced:
                if chunk == 1:
                    break
                n = min(len(lines), n * 2)
    return best
