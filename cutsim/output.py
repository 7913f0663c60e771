"""Writing a run's files into the output directory DIR as one transaction.

A run stages its files in a private directory beside DIR (``.cutsim-tmp-XXXXXXXX`` in DIR's
parent, same filesystem) and moves them into place only when every file was written:

- DIR missing or empty: ``rename(staging, DIR)`` (atomic).
- DIR holding only files of an earlier cutsim run (those listed in ``DIR/.cutsim-output.json``):
  ``renameat2(RENAME_EXCHANGE)`` swaps the two directories in one step (Linux; atomic), then the
  old files are removed.
- DIR holding anything else (a user's files), or no exchange on this system: each output file is
  renamed over its old version (each file atomic, the set not), earlier cutsim files this run did
  not write are removed, and the marker is rewritten last. A user's files are never touched.

``DIR/.cutsim-output.json`` lists the files cutsim wrote (sorted names; same bytes for the same
set). Until the commit nothing in DIR changes, so a run that fails, is interrupted or is killed
(SIGKILL too) leaves the previous output as it was. Staging directories hold a ``flock`` while
their run lives; the next run in the same parent removes those whose run is gone.
"""
from __future__ import annotations

import contextlib
import ctypes
import errno
import fcntl
import json
import os
import re
import signal
import stat
import sys
import tempfile

from cutsim.interp.errors import CutsimError

MARKER = ".cutsim-output.json"
STAGING_PREFIX = ".cutsim-tmp-"
_STAGING_RE = re.compile(r"\.cutsim-tmp-[A-Za-z0-9_]{8}\Z")
_INTERIM = ".cutsim-interim.json"  # the marker while a per-file commit is under way
_NO_EXCHANGE = {errno.ENOSYS, errno.EINVAL, errno.EOPNOTSUPP, errno.EXDEV, errno.EBUSY, errno.EPERM,
                errno.ENOTSUP}


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_outputs(out_dir: str, files: dict[str, bytes]) -> None:
    """Write ``files`` (name -> bytes) into ``out_dir`` as one transaction (see the module doc).
    Raises CutsimError naming the path when the directory cannot be written."""
    with Output(out_dir, files) as out:
        out.commit(files)


class Output:
    """One run's output transaction. ``Output(DIR, names)`` checks DIR before the work starts
    (CutsimError naming the path when it cannot be written) and clears stale staging directories;
    ``commit(files)`` writes and moves the files into place; ``abort()`` (or leaving the ``with``
    block without a commit) removes the staging directory and leaves DIR untouched."""

    def __init__(self, out_dir: str, names=()):
        self.user_dir = out_dir
        self.committed = False
        self._staging = None
        self._lock_fd = None
        self._placed = False
        self._check_path(out_dir)
        self.dir = os.path.realpath(out_dir)
        for name in names:
            self._check_target(name)
        if os.path.isdir(os.path.dirname(self.dir)):  # else at the commit, with DIR's parents
            self._stage()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.abort()
        return False

    # ---- checks before the run -------------------------------------------------------------
    def _error(self, text: str, path: str | None = None):
        return CutsimError(self.user_dir if path is None else path, 0, 0, f"--out: {text}")

    def _check_path(self, out_dir: str) -> None:
        if out_dir == "":
            raise CutsimError("cutsim", 0, 0, "--out: the output directory name is empty")
        if "\0" in out_dir:
            raise CutsimError("cutsim", 0, 0, "--out: the output directory name contains a NUL byte")
        if os.path.basename(os.path.abspath(out_dir)).startswith(STAGING_PREFIX):
            raise self._error(f"names starting with {STAGING_PREFIX} are cutsim's temporary directories")
        try:
            st = os.stat(out_dir)
        except FileNotFoundError:
            st = None
        except NotADirectoryError:
            raise self._error(f"{_not_dir_ancestor(out_dir)} is not a directory") from None
        except OSError as e:
            raise self._error(f"cannot use it: {e.strerror}") from None
        if st is not None:
            if not stat.S_ISDIR(st.st_mode):
                raise self._error(f"not a directory ({_kind(st.st_mode)})")
            if not os.access(out_dir, os.W_OK | os.X_OK):
                raise self._error("cannot write into it (permission denied or a read-only filesystem)")
            return
        anc = os.path.dirname(os.path.abspath(out_dir))
        while not os.path.lexists(anc):
            anc = os.path.dirname(anc)
        if not os.path.isdir(anc):
            raise self._error(f"{anc} is not a directory")
        if not os.access(anc, os.W_OK | os.X_OK):
            raise self._error(f"cannot create it in {anc} (permission denied or a read-only filesystem)")
        name_max = _pathconf(anc, "PC_NAME_MAX", 255)
        path_max = _pathconf(anc, "PC_PATH_MAX", 4096)
        rest = os.path.relpath(os.path.abspath(out_dir), anc)
        if any(len(os.fsencode(part)) > name_max for part in rest.split(os.sep)) or \
                len(os.fsencode(os.path.abspath(out_dir))) >= path_max:
            raise self._error(f"cannot create it: {os.strerror(errno.ENAMETOOLONG)}")

    def _check_target(self, name: str) -> None:
        """DIR/name must not be a directory or another non-file (it will be replaced by a file)."""
        if not _plain_name(name) or name == MARKER or name == _INTERIM:
            raise ValueError(f"bad output file name {name!r}")
        try:
            st = os.lstat(os.path.join(self.dir, name))
        except FileNotFoundError:
            return
        except OSError as e:
            raise self._error(f"cannot use it: {e.strerror}", os.path.join(self.user_dir, name)) from None
        if not (stat.S_ISREG(st.st_mode) or stat.S_ISLNK(st.st_mode)):
            raise self._error(f"is {_kind(st.st_mode)}, cutsim writes a file of that name",
                              os.path.join(self.user_dir, name))

    def _stage(self) -> None:
        """Create the staging directory beside DIR; inside DIR when DIR is a mount point (or /)
        or its parent is not writable (the commit is then per file)."""
        parent = os.path.dirname(self.dir)
        if parent != self.dir and not os.path.ismount(self.dir):
            try:
                os.makedirs(parent, exist_ok=True)
            except OSError as e:
                raise self._error(f"cannot create {e.filename or parent}: {e.strerror}") from None
            _clean_stale(parent)
            try:
                self._make_staging(parent)
                return
            except OSError as e:
                if not (os.path.isdir(self.dir) and e.errno in (errno.EACCES, errno.EPERM, errno.EROFS)):
                    raise self._error(f"cannot create a temporary directory in {parent}: {e.strerror}") from None
        _clean_stale(self.dir)
        try:
            self._make_staging(self.dir)
        except OSError as e:
            raise self._error(f"cannot create a temporary directory in it: {e.strerror}") from None

    def _make_staging(self, parent: str) -> None:
        for _ in range(100):
            path = tempfile.mkdtemp(prefix=STAGING_PREFIX, dir=parent)
            fd = os.open(path, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
                same = os.stat(path).st_ino == os.fstat(fd).st_ino
            except OSError:  # a stale-cleaner took it between mkdtemp and flock
                same = False
            if same:
                self._staging, self._lock_fd = path, fd
                return
            os.close(fd)
        raise OSError(errno.EEXIST, "cannot create a temporary directory", parent)

    # ---- commit ----------------------------------------------------------------------------
    def commit(self, files: dict[str, bytes]) -> None:
        """Write ``files`` into the staging directory, then move them into DIR (module doc)."""
        names = sorted(files)
        for name in names:
            self._check_target(name)
        try:
            if self._staging is None:
                self._stage()
            self._write_staging(files, names)
            with _signals_blocked(), _dir_lock(os.path.dirname(self._staging)):
                self._place(names)
                self.committed = True  # before a Ctrl-C held back during the commit is raised
        finally:
            self.abort()

    def _write_staging(self, files, names) -> None:
        marker = _marker_bytes(names)
        for name, data in [(MARKER, marker)] + [(n, files[n]) for n in names]:
            path = os.path.join(self._staging, name)
            try:
                fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_CLOEXEC, 0o666)
                try:
                    view = memoryview(data)
                    while view:
                        view = view[os.write(fd, view):]
                    os.fsync(fd)
                finally:
                    os.close(fd)
            except OSError as e:
                raise self._error(f"cannot write it: {e.strerror}", os.path.join(self.user_dir, name)) from None
        _fsync_dir(self._staging)

    def _place(self, names) -> None:
        for _ in range(5):  # DIR may change under us (another process): look again
            try:
                st = os.lstat(self.dir)
            except FileNotFoundError:
                st = None
            except OSError as e:
                raise self._error(f"cannot use it: {e.strerror}") from None
            if st is not None and not stat.S_ISDIR(st.st_mode):
                raise self._error(f"not a directory ({_kind(st.st_mode)})")
            for name in names:
                self._check_target(name)
            if os.path.dirname(self._staging) == self.dir:
                self._per_file(names)  # staged inside DIR (a mount point, or its parent is read-only)
                return
            old = _read_marker(self.dir) if st else set()
            entries = _entries(self.dir) if st else []
            try:
                if not entries:  # DIR missing or empty: one rename
                    os.chmod(self._staging, stat.S_IMODE(st.st_mode) if st else 0o777 & ~_umask())
                    os.rename(self._staging, self.dir)
                    self._placed = True
                    _fsync_dir(os.path.dirname(self.dir))
                    return
                if all(e.name == MARKER or (e.name in old and e.is_file(follow_symlinks=False)) for e in entries):
                    _copy_dir_owner(st, self._staging)
                    try:
                        _exchange(self._staging, self.dir)
                    except OSError as e:
                        if e.errno not in _NO_EXCHANGE:
                            raise
                    else:
                        self._placed = True
                        _fsync_dir(os.path.dirname(self.dir))
                        _remove_owned(self._staging, old, restore_to=self.dir)
                        return
            except FileNotFoundError:
                continue
            except OSError as e:
                if e.errno in (errno.ENOTEMPTY, errno.EEXIST):
                    continue
                raise self._error(f"cannot write it: {e.strerror}") from None
            self._per_file(names)
            return
        raise self._error("it keeps changing while cutsim writes it")

    def _per_file(self, names) -> None:
        """Each file renamed over its old version; the marker lists old and new cutsim files
        while this runs, so an interrupted commit never leaves a cutsim file unlisted."""
        old = _read_marker(self.dir)
        new = set(names)
        try:
            interim = os.path.join(self._staging, _INTERIM)
            with open(interim, "wb") as f:
                f.write(_marker_bytes(sorted(old | new)))
            os.replace(interim, os.path.join(self.dir, MARKER))
            for name in names:
                os.replace(os.path.join(self._staging, name), os.path.join(self.dir, name))
            for name in sorted(old - new):
                p = os.path.join(self.dir, name)
                with contextlib.suppress(FileNotFoundError):
                    if not stat.S_ISDIR(os.lstat(p).st_mode):
                        os.unlink(p)
            os.replace(os.path.join(self._staging, MARKER), os.path.join(self.dir, MARKER))
        except OSError as e:
            raise self._error(f"cannot write it: {e.strerror}") from None
        self._placed = True
        with contextlib.suppress(OSError):
            os.rmdir(self._staging)
        _fsync_dir(self.dir)

    def abort(self) -> None:
        """Remove the staging directory (unless it became DIR) and release its lock."""
        if self._staging is not None and not self._placed:
            _remove_owned(self._staging, None)
        self._staging = None
        if self._lock_fd is not None:
            os.close(self._lock_fd)
            self._lock_fd = None


# ---- helpers -------------------------------------------------------------------------------
def _plain_name(name: str) -> bool:
    return bool(name) and name not in (".", "..") and "/" not in name and "\0" not in name \
        and not name.startswith(STAGING_PREFIX)


def _marker_bytes(names) -> bytes:
    return (json.dumps({"written_by": "cutsim", "files": sorted(names)}, indent=1) + "\n").encode()


def _read_marker(d: str) -> set[str]:
    """The file names DIR's marker lists (empty when it is missing or not cutsim's)."""
    try:
        fd = os.open(os.path.join(d, MARKER), os.O_RDONLY | os.O_NOFOLLOW | os.O_CLOEXEC | os.O_NONBLOCK)
    except OSError:
        return set()
    try:
        if not stat.S_ISREG(os.fstat(fd).st_mode):
            return set()
        with os.fdopen(fd, "rb", closefd=False) as f:
            data = json.loads(f.read(1 << 20).decode("utf-8"))
    except (OSError, ValueError):
        return set()
    finally:
        os.close(fd)
    files = data.get("files") if isinstance(data, dict) and data.get("written_by") == "cutsim" else None
    if not isinstance(files, list):
        return set()
    return {n for n in files if isinstance(n, str) and _plain_name(n) and n not in (MARKER, _INTERIM)}


def _entries(d: str) -> list:
    with os.scandir(d) as it:
        return list(it)


def _remove_owned(d: str, owned: set[str] | None, restore_to: str | None = None) -> None:
    """Remove a staging (or swapped-out old output) directory: the files its marker lists (all of
    them when ``owned`` is None: our own staging), the markers, then the directory. Anything else
    (a user's file that slipped in) is moved back to ``restore_to`` or left where it is."""
    if owned is None:
        owned = _read_marker(d) | {n for n in _safe_listdir(d)}
    for name in owned | {MARKER, _INTERIM}:
        p = os.path.join(d, name)
        with contextlib.suppress(OSError):
            if not stat.S_ISDIR(os.lstat(p).st_mode):
                os.unlink(p)
    if restore_to is not None:
        for name in _safe_listdir(d):
            dst = os.path.join(restore_to, name)
            if not os.path.lexists(dst):
                with contextlib.suppress(OSError):
                    os.rename(os.path.join(d, name), dst)
    with contextlib.suppress(OSError):
        os.rmdir(d)


def _safe_listdir(d: str) -> list[str]:
    try:
        return os.listdir(d)
    except OSError:
        return []


def _clean_stale(parent: str) -> None:
    """Remove staging directories of runs that are gone (their flock is free)."""
    for name in _safe_listdir(parent):
        if not _STAGING_RE.match(name):
            continue
        path = os.path.join(parent, name)
        try:
            fd = os.open(path, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW | os.O_CLOEXEC)
        except OSError:
            continue
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except OSError:
            os.close(fd)  # its run is alive
            continue
        try:
            _remove_owned(path, _read_marker(path))
        finally:
            os.close(fd)


@contextlib.contextmanager
def _dir_lock(d: str):
    """Serialise commits in one directory (flock on it; skipped where it cannot be opened)."""
    try:
        fd = os.open(d, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
    except OSError:
        yield
        return
    try:
        fcntl.flock(fd, fcntl.LOCK_EX)
        yield
    finally:
        os.close(fd)


@contextlib.contextmanager
def _signals_blocked():
    """Ctrl-C, SIGTERM and SIGHUP wait until the files are in place (a few renames)."""
    sigs = {signal.SIGINT, signal.SIGTERM, signal.SIGHUP}
    old = signal.pthread_sigmask(signal.SIG_BLOCK, sigs)
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, old)


def _fsync_dir(d: str) -> None:
    with contextlib.suppress(OSError):
        fd = os.open(d, os.O_RDONLY | os.O_DIRECTORY | os.O_CLOEXEC)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)


def _copy_dir_owner(st, path: str) -> None:
    """The swapped-in directory keeps the old DIR's mode (and owner, when cutsim may set it)."""
    os.chmod(path, stat.S_IMODE(st.st_mode))
    if os.geteuid() == 0 and (st.st_uid, st.st_gid) != (os.geteuid(), os.getegid()):
        with contextlib.suppress(OSError):
            os.chown(path, st.st_uid, st.st_gid)


_RENAMEAT2 = []


def _renameat2():
    """libc's renameat2 (glibc >= 2.28) or the raw syscall; None off Linux."""
    if not _RENAMEAT2:
        fn = None
        if sys.platform.startswith("linux"):
            try:
                libc = ctypes.CDLL(None, use_errno=True)
                f = getattr(libc, "renameat2", None)
                if f is not None:
                    f.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p, ctypes.c_uint]
                    f.restype = ctypes.c_int
                    fn = f
                else:
                    nr = {"x86_64": 316, "aarch64": 276, "riscv64": 276}.get(os.uname().machine)
                    if nr is not None:
                        sc = libc.syscall
                        sc.restype = ctypes.c_long

                        def fn(a, b, c, d, e, _sc=sc, _nr=nr):
                            return _sc(ctypes.c_long(_nr), ctypes.c_int(a), ctypes.c_char_p(b), ctypes.c_int(c),
                                       ctypes.c_char_p(d), ctypes.c_uint(e))
            except OSError:
                fn = None
        _RENAMEAT2.append(fn)
    return _RENAMEAT2[0]


def _exchange(a: str, b: str) -> None:
    """Swap two paths atomically (renameat2 RENAME_EXCHANGE); OSError(ENOSYS) where unavailable."""
    fn = _renameat2()
    if fn is None:
        raise OSError(errno.ENOSYS, os.strerror(errno.ENOSYS))
    if fn(-100, os.fsencode(a), -100, os.fsencode(b), 2) != 0:  # AT_FDCWD, RENAME_EXCHANGE
        err = ctypes.get_errno()
        raise OSError(err, os.strerror(err), a, None, b)


def _pathconf(path: str, name: str, default: int) -> int:
    try:
        return os.pathconf(path, name) or default
    except (OSError, ValueError):
        return default


def _not_dir_ancestor(path: str) -> str:
    """The first component of ``path`` (as the user wrote it) that exists and is not a directory."""
    parts = path.split(os.sep)
    for i in range(1, len(parts)):
        if not parts[i - 1]:
            continue  # the leading "/" (or a doubled one)
        prefix = os.sep.join(parts[:i])
        try:
            st = os.stat(prefix)
        except OSError:
            break
        if not stat.S_ISDIR(st.st_mode):
            return prefix
    return path


_KINDS = ((stat.S_ISREG, "a file"), (stat.S_ISDIR, "a directory"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISFIFO, "a named pipe"), (stat.S_ISSOCK, "a socket"),
          (stat.S_ISLNK, "a symbolic link"))


def _kind(mode: int) -> str:
    return next((name for test, name in _KINDS if test(mode)), "not a regular file")
