"""Process supervision: run one command in its own session under a time limit and an address-space
limit, stop it (SIGTERM to its process group, SIGKILL after a grace period), and stop every
supervised process at once (Ctrl-C of the batch). Also what another supervisor of worker processes
needs (tests/support/fuzz_cases.py): the same limits applied in a child, and a process's CPU time.
"""
from __future__ import annotations

import os
import signal
import subprocess
import threading
import time

GRACE = 5.0  # s between SIGTERM and SIGKILL (cutsim cleans up and exits 143 on SIGTERM)

_RUNNING: dict[int, subprocess.Popen] = {}
_RUNNING_LOCK = threading.Lock()
STOP = threading.Event()  # set by terminate_all: jobs not yet started do not start


def set_limits(memory_mib: int) -> None:
    """In the child (before exec, or first thing in a forked worker): no core files, and at most
    ``memory_mib`` MiB of address space (RLIMIT_AS; 0: no limit)."""
    import resource

    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    if memory_mib:
        lim = memory_mib << 20
        resource.setrlimit(resource.RLIMIT_AS, (lim, lim))


def run_limited(argv, timeout: float, memory_mib: int, cwd: str | None = None):
    """Run ``argv`` in its own session under the limits, stdout discarded and stderr captured:
    (returncode, stderr text, timed_out, seconds). A command that cannot start is returncode None."""
    t0 = time.monotonic()
    env = dict(os.environ)
    env.pop("CUTSIM_DEBUG", None)
    env.setdefault("PYTHONHASHSEED", "0")
    try:
        p = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                             preexec_fn=lambda: set_limits(memory_mib), start_new_session=True, cwd=cwd, env=env)
    except OSError as e:
        return None, f"cannot start the job: {e}", False, 0.0
    with _RUNNING_LOCK:
        _RUNNING[p.pid] = p
    timed_out = False
    try:
        try:
            _, err = p.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            timed_out = True
            stop(p)
            _, err = p.communicate()
    finally:
        with _RUNNING_LOCK:
            _RUNNING.pop(p.pid, None)
    return p.returncode, err.decode("utf-8", "replace"), timed_out, time.monotonic() - t0


def stop(p: subprocess.Popen, grace: float = GRACE) -> None:
    """SIGTERM to the process group of ``p`` (started with its own session), SIGKILL after ``grace``."""
    for sig, wait in ((signal.SIGTERM, grace), (signal.SIGKILL, None)):
        try:
            os.killpg(p.pid, sig)
        except (ProcessLookupError, PermissionError):
            return
        try:
            p.wait(timeout=wait)
            return
        except subprocess.TimeoutExpired:
            continue


def terminate_all() -> None:
    """Stop every process run_limited is supervising (in parallel) and let no new one start until
    STOP is cleared."""
    STOP.set()
    with _RUNNING_LOCK:
        procs = list(_RUNNING.values())
    threads = [threading.Thread(target=stop, args=(p, GRACE)) for p in procs]
    for t in threads:
        t.start()
    for t in threads:
        t.join()


def cpu_seconds(pid: int) -> float:
    """User + system CPU time of a process (all its threads), from /proc; 0 where unavailable."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as f:
            fields = f.read().rsplit(b")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError):
        return 0.0
