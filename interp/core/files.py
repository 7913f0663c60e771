"""Program files: bounded reads and the subprogram search (the main program's folder, then the
setup's folders). A device, a pipe, a directory or a file larger than its limit is refused before
it is read: a program never makes the simulator read without end."""
from __future__ import annotations

import os
import stat


class Unreadable(Exception):
    """Why a file was not read. ``kind``: "directory", "special" (device, pipe, socket), "large"
    (``size`` bytes, more than the limit; -1 when it grew while being read) or "os" (``reason``:
    the system's error text)."""

    def __init__(self, kind: str, reason: str = "", size: int = -1):
        super().__init__(kind, reason, size)
        self.kind, self.reason, self.size = kind, reason, size


def read_bounded(path: str, limit: int) -> bytes:
    """The bytes of the regular file ``path`` of at most ``limit`` bytes; Unreadable otherwise."""
    try:
        # O_NONBLOCK: opening a named pipe must not wait for a writer (regular files ignore it)
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except OSError as e:
        raise Unreadable("os", e.strerror) from None
    except ValueError:  # a NUL byte in the name
        raise Unreadable("os", "the file name contains a NUL byte") from None
    try:
        st = os.fstat(fd)
        if stat.S_ISDIR(st.st_mode):
            raise Unreadable("directory")
        if not stat.S_ISREG(st.st_mode):
            raise Unreadable("special")
        if st.st_size > limit:
            raise Unreadable("large", size=st.st_size)
        with os.fdopen(os.dup(fd), "rb") as f:
            raw = f.read(limit + 1)
    except OSError as e:
        raise Unreadable("os", e.strerror) from None
    finally:
        os.close(fd)
    if len(raw) > limit:  # grew while being read
        raise Unreadable("large")
    return raw


def find_subprogram(name: str, dirs, extensions) -> str | None:
    """The file a subprogram call names: the first folder of ``dirs`` holding ``name`` with one of
    ``extensions`` ("" for the name as written), compared without case; a path written for the
    controller (C:\\...\\name.nc) is looked up by its file name. None when no folder has it."""
    base = name.replace("\\", "/").rsplit("/", 1)[-1]
    wanted = {(base + ext).upper() for ext in extensions}
    for d in dirs:
        try:
            names = sorted(os.listdir(d))
        except OSError:
            continue
        for n in names:
            if n.upper() in wanted:
                return os.path.join(d, n)
    return None
