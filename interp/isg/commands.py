"""ISG ``#`` commands (docs/dialects/isg.md, "# commands"): those that do not change the tool path
pass with one warning each; ``#CS`` translations are applied; what the simulator cannot model
(kinematic transformations, RTCP, rotated coordinate systems) stops with exit 2 naming it.
"""
from __future__ import annotations

import math
import re

from ..errors import CutsimError
from .lang import Cursor, expression

# commands without effect on the tool path -> what they do
PASSIVE = {
    "MSG": "operator message", "FLUSH": "wait for the block preparation", "CONTOUR": "contouring mode",
    "HSC": "high speed cutting settings", "CHANNEL": "channel settings", "FILENAME": "file name for output",
    "IDENT": "program identification", "DELETE": "delete", "VECTOR": "vector velocity limits",
    "TOOL": "tool data", "ORI": "orientation mode", "KIN": "kinematics selection (acts with #TRAFO ON)",
    "TIME": "time settings", "SLOPE": "acceleration profile", "SET": "settings", "EXPORT": "export",
    "SIGNAL": "signal", "WAIT": "wait", "TIMER": "timer", "OPTIONAL": "optional execution", "SYN": "synchronisation",
    "MEAS": "measurement settings", "SUPPRESS": "suppress", "STROKE": "stroke settings", "CLEAR": "clear",
    "AX": "axis settings", "CAX": "C axis settings", "PROG": "program settings", "PUT": "put", "INIT": "init",
    "MACHINE": "machine data", "AXLINK": "axis link", "PATH": "path settings", "OVERRIDE": "override",
    "ACHSE": "axis settings", "SAVE": "save", "RESTORE": "restore", "FGROUP": "feed axes group",
    "PROG_END": "program end settings", "SPLINE_TYPE": "spline type",
}
# commands whose ON form changes the tool path in a way the simulator does not model
NOT_MODELLED = {
    "TRAFO": "a kinematic transformation", "RTCP": "tool centre point control (RTCP)",
    "TLAX": "a tool axis transformation", "ACS": "an axial coordinate system", "CYL": "a cylinder transformation",
    "TRANS": "a transformation", "FACE": "face machining", "PTP": "point-to-point motion",
    "SPLINE": "spline interpolation", "TANGFEED": "tangential feed", "BCS": "a basic coordinate system",
    "PCS": "a part coordinate system", "KINORG": "a kinematic origin", "MIRROR": "mirroring",
    "SCALE": "scaling", "POLAR": "polar coordinates", "AKT": "transformations",
}



class Commands:
    """The ``#`` commands of Isg (a part of it): the state they change is the frames' (#CS,
    #ROTATION), the calls' (#FILE NAME) and the variables' (#DELETE)."""

    def cmd_passive(self, st, name: str, text: str) -> None:
        what = PASSIVE.get(name, "")
        w = re.match(r"[A-Za-z]+", text)
        self.warn_once(("#", name), st.src, f"#{name}{' ' + w.group(0).upper() if w else ''} ({what}) does not "
                    "change the tool path: accepted, not simulated")

    def cmd_delete(self, st, text: str, col: int) -> None:
        """``#DELETE V.P.NAME`` (also several, separated by commas or blanks): the user variables are
        deleted (manual: "Self-defined variables (#VAR, #ENDVAR, #DELETE)"); a name that does not exist
        and a controller variable (V.E., V.G., V.A.) are errors, as on the controller (IDs 20932, 20931)."""
        line = st.block.line
        for name in re.split(r"[\s,]+", text.split(";", 1)[0].strip()):
            if not name:
                continue
            key = name.upper()
            if not re.fullmatch(r"V\.[PLS]\.[A-Z_][A-Z0-9_.]*", key):
                raise self.error(line, col, f"#DELETE {name}: only user variables V.P., V.L. and V.S. can be deleted "
                              "(the controller's error 20931)")
            store = self.level.vl if key[2] == "L" else self.vars
            if key not in store:
                raise self.error(line, col, f"#DELETE {name}: the variable does not exist (the controller's error 20932)")
            for k in [k for k in store if k == key or k.startswith(key + "[")]:
                del store[k]
            self.declared.pop(key, None)

    def command(self, st, name: str, text: str, col: int) -> None:
        """Run one ``#`` command of block ``st``."""
        line = st.block.line
        head = text.split("[", 1)[0].split()
        first = head[0].upper() if head else ""
        if name == "DELETE" and text.lstrip()[:2].upper() == "V.":
            return self.cmd_delete(st, text, col)
        if name in PASSIVE:
            self.cmd_passive(st, name, text)
            return
        if name == "DIST_CTRL":
            return self.cmd_dist_ctrl(st, text, col)
        if name == "ERROR":  # the program stops the controller with an error here
            raise self.error(line, col, f"#ERROR {text}: the program raises an error here (the controller stops)")
        if name == "CS":
            return self.cmd_cs(st, text, col)
        if name == "FILE":
            return self.cmd_file_names(st, text, col)
        if name == "DISABLE" and first == "MODAL":  # #DISABLE MODAL CYCLE: the level's modal cycle call ends
            self.level.modal = None
            return
        if name == "MCS":
            if first == "OFF":
                return
            raise self.error(line, col, f"#MCS {first}: motion in machine coordinates (offsets and tool length switched "
                          "off) is not modelled by the simulator")
        if name == "ROTATION":
            return self.cmd_rotation(st, text, col, first)
        if name == "TRAFO" and first != "OFF":
            if "TRAFO" in self.cfg.transformations:
                self.warn_once(("#", "TRAFO"), st.src, "#TRAFO ON: the setup declares the transformation Cartesian "
                            "([machine] transformations = [\"TRAFO\"]): the program's X/Y/Z are simulated as they are")
                return
            raise self.error(line, col, f"#TRAFO {first}: a kinematic transformation is not modelled by the simulator; if "
                          "this machine's transformation is Cartesian (a gantry or robot programmed in workpiece "
                          "coordinates), declare it in the setup: [machine] transformations = [\"TRAFO\"]")
        if name in NOT_MODELLED:
            if first == "OFF" or (name in ("TRAFO", "RTCP", "TLAX", "ACS", "CYL", "TRANS", "FACE", "BCS", "PCS",
                                           "MIRROR", "SCALE", "POLAR") and first == "OFF"):
                self.warn_once(("#", name, "OFF"), st.src, f"#{name} OFF: nothing to switch off in the simulation")
                return
            raise self.error(line, col, f"#{name} {first}: {NOT_MODELLED[name]} is not modelled by the simulator "
                          "(exit rather than a wrong tool path)")
        raise self.error(line, col, f"#{name} is not known to the simulator")

    def cmd_values(self, st, text: str, i: int, col: int) -> tuple[list, int]:
        """A bracketed list ``[a, b, , c]`` at ``text[i]`` -> (values, None where empty), index after it."""
        depth, j, parts, start = 0, i + 1, [], i + 1
        while j < len(text):
            c = text[j]
            if c == "[":
                depth += 1
            elif c == "]":
                if depth == 0:
                    parts.append((start, text[start:j]))
                    break
                depth -= 1
            elif c == "," and depth == 0:
                parts.append((start, text[start:j]))
                start = j + 1
            j += 1
        else:
            raise CutsimError(self.name, st.block.line, col, "']' expected to close the list")
        out = []
        for k, piece in parts:
            if not piece.strip():
                out.append(None)
                continue
            cur = Cursor(self.name, st.block.line, text, k)
            v = expression(cur)(self)
            cur.skip()
            if cur.i != k + len(piece):
                raise cur.error("',' or ']' expected")
            if isinstance(v, str):
                raise CutsimError(self.name, st.block.line, col, f"\"{v}\" is not a number")
            out.append(v)
        return out, j + 1

    def cmd_cs(self, st, text: str, col: int) -> None:
        """#CS DEF [id] [v1,v2,v3,a1,a2,a3], #CS ON [id] [...], #CS ON [id], #CS ON, #CS OFF [ALL],
        #CS MODE ...: translations are applied; a rotation that is not a whole turn is an error."""
        line = st.block.line
        s = text.strip()
        mm = re.match(r"([A-Za-z]+)\s*(.*)$", s)
        if not mm:
            raise self.error(line, col, "#CS needs DEF, ON or OFF")
        op, rest = mm.group(1).upper(), mm.group(2)
        if op == "MODE":
            self.warn_once(("#", "CS MODE"), st.src, "#CS MODE does not change the tool path here: accepted")
            return
        if op == "OFF":
            if rest.strip().upper().startswith("ALL"):
                self.cs.clear()
            elif self.cs:
                self.cs.pop()
            self.frame_changed(line, col)
            return
        if op not in ("DEF", "ON"):
            raise self.error(line, col, f"#CS {op}: only #CS DEF, #CS ON and #CS OFF are known")
        lists = []
        i = 0
        while i < len(rest):
            if rest[i] == "[":
                vals, i = self.cmd_values(st, rest, i, col)
                lists.append(vals)
            elif rest[i] in " \t":
                i += 1
            else:
                raise self.error(line, col, f"unexpected '{rest[i]}' in #CS {op}")
        ident, vec = None, None
        if len(lists) == 2:
            ident, vec = lists
        elif len(lists) == 1 and (len(lists[0]) > 1 or op == "DEF"):
            vec = lists[0]
        elif len(lists) == 1:
            ident = lists[0]
        ident = int(ident[0]) if ident and ident[0] is not None else None
        if vec is not None:
            comps = [0.0 if v is None else float(v) for v in vec] + [0.0] * 6
            rot = comps[3:6]
            tilted = [f"{'XY'[k]} by {rot[k]:g} degrees" for k in (0, 1) if rot[k] % 360 != 0]
            if tilted:
                raise self.error(line, col, f"#CS {op} with a rotation about {' and about '.join(tilted)} is not modelled by "
                              "the simulator (a tilted machining plane needs a rotary tool axis); only translations and a "
                              "rotation about the tool axis Z are applied")
            t = (comps[0], comps[1], comps[2], rot[2])
            key = ident if ident is not None else (max(self.cs_defs) + 1 if self.cs_defs else 1)
            self.cs_defs[key] = t
            self.cs_last = key
            if op == "ON":
                self.cs.append(t)
                self.frame_changed(line, col)
            return
        key = ident if ident is not None else self.cs_last
        if key is None or key not in self.cs_defs:
            raise self.error(line, col, f"#CS ON{'' if ident is None else f' [{ident}]'}: no coordinate system "
                          f"{'defined' if ident is None else str(ident) + ' defined'} (#CS DEF first)")
        self.cs.append(self.cs_defs[key])
        if not all(math.isfinite(v) for v in self.cs_defs[key]):  # pragma: no cover - values come from expressions
            raise self.error(line, col, "#CS values out of range")
        self.frame_changed(line, col)

    def cmd_file_names(self, st, text: str, col: int) -> None:
        """#FILE NAME [G80 = "file.nc", MSG = ...]: the files behind implicit subroutine calls (G80..G89,
        G800..G819) for the rest of the run; other entries only name output files (one warning)."""
        found = False
        for mm in re.finditer(r"\b(G[0-9]+)\s*=\s*(\"[^\"]*\"|[^\s,\]]+)", text, re.I):
            code = mm.group(1).upper()
            self.implicit_files[code] = mm.group(2).strip('"')
            found = True
        if not found:
            self.cmd_passive(st, "FILE", text)

    def cmd_dist_ctrl(self, st, text: str, col: int) -> None:
        """``Z[DIST_CTRL [WAIT] OFF [NO_MOVE]]`` / ``FREEZE``: distance control (a sensor makes the axis
        follow the workpiece surface) off or frozen - the simulator never has it on, so nothing moves:
        one warning. ``ON``, ``DRYRUN``, ``REF``, ``CHECK_POS``: the axis would follow a sensor or a
        measurement the simulator does not have: exit 2."""
        axis, _, rest = text.partition(" ")
        words = [w.upper() for w in re.findall(r"[A-Za-z_]+", rest)][1:]
        words = [w for w in words if w != "WAIT"]
        mode = words[0] if words else ""
        if mode in ("OFF", "FREEZE", "NO_MOVE"):
            self.warn_once(("#", "DIST_CTRL"), st.src, f"{axis}[DIST_CTRL {mode}] (distance control off) does not change the "
                        "tool path in the simulation (distance control is never on here): accepted")
            return
        raise self.error(st.block.line, col, f"{axis}[DIST_CTRL {mode or '...'}]: distance control (the axis follows a sensor "
                      "on the workpiece surface) is not modelled by the simulator")

    def cmd_rotation(self, st, text: str, col: int, first: str) -> None:
        """``#ROTATION ON [ANGLE = a CENTER1 = c1 CENTER2 = c2]`` (``=`` optional) / ``#ROTATION OFF``:
        contour rotation in the current plane by ``a`` degrees about the point (c1, c2) of its two main
        axes (manual: "Rotation in a plane (contour rotation)"); missing values are 0."""
        line = st.block.line
        if first == "OFF":
            self.rotation = None
            self.frame_changed(line, col)
            return
        if first != "ON":
            raise self.error(line, col, "#ROTATION needs ON or OFF")
        pad = col + len("ROTATION") + 1  # where the text starts in the line (one blank after the name, as written)
        text = " " * pad + text
        i = text.upper().index("ON", pad) + 2
        vals = {"ANGLE": 0.0, "CENTER1": 0.0, "CENTER2": 0.0}
        cur = Cursor(self.name, line, text, i)
        cur.skip()
        if cur.peek() == "[":
            cur.i += 1
            while True:
                cur.skip()
                if cur.peek() == "]":
                    cur.i += 1
                    break
                key = next((k for k in vals if cur.at_word(k)), None)
                if key is None:
                    raise self.error(line, col, f"#ROTATION ON [...]: ANGLE, CENTER1 or CENTER2 expected at '{text[cur.i:cur.i + 10]}'")
                cur.i += len(key)
                cur.skip()
                if cur.peek() == "=":
                    cur.i += 1
                v = expression(cur)(self)
                if isinstance(v, str):
                    raise self.error(line, col, f"#ROTATION {key}: \"{v}\" is not a number")
                vals[key] = float(v)
                cur.skip()
                if cur.peek() == ",":
                    cur.i += 1
        cur.skip()
        if cur.i < len(text):
            raise self.error(line, col, f"unexpected '{text[cur.i]}' after #ROTATION ON [...]")
        self.rotation = (vals["ANGLE"], self.plane, vals["CENTER1"], vals["CENTER2"])
        self.frame_changed(line, col)
