"""Progress of a batch on stderr: jobs done / failed / running with an ETA, as a tqdm bar on a
terminal and as one plain line per finished job otherwise (a CI log)."""
from __future__ import annotations

import sys
import threading
import time

import click

from .records import PASSED


class Bar:
    """Jobs done / failed / running with an ETA on stderr: tqdm on a terminal, plain lines otherwise."""

    def __init__(self, total, resumed, enabled):
        self.total, self.n, self.failed, self.running = total, resumed, 0, 0
        self.enabled = enabled and total > 0
        self.slots = None
        self.seen = set()
        self.lock = threading.Lock()
        self.tty = self.enabled and sys.stderr.isatty()
        self.t0 = time.monotonic()
        self.bar = None
        if self.tty:
            from tqdm import tqdm

            self.bar = tqdm(total=total, initial=resumed, desc="batch", unit="job", file=sys.stderr,
                            dynamic_ncols=True)
            self._post()
        elif self.enabled and resumed:
            click.echo(f"cutsim batch: {resumed} of {total} jobs resumed", err=True)

    def started(self):
        with self.lock:
            self.running += 1
            self._post()

    def stopped(self):
        with self.lock:
            self.running -= 1

    def _post(self):
        if self.bar is not None:
            running = self.running if self.slots is None else min(self.slots, self.total - self.n)
            self.bar.set_postfix_str(f"failed {self.failed}, running {running}", refresh=True)

    def update(self, name, rec):
        with self.lock:
            self.seen.add(name)
            self.n += 1
            if rec["status"] != PASSED:
                self.failed += 1
            if not self.enabled:
                return
            if self.bar is not None:
                self.bar.update(1)
                self._post()
            else:
                el = time.monotonic() - self.t0
                eta = f", ETA {el / max(1, len(self.seen)) * (self.total - self.n):.0f} s" if self.n < self.total else ""
                click.echo(f"cutsim batch: [{self.n}/{self.total}] {name}: {rec['status']}"
                           f"{': ' + rec['message'] if rec['message'] else ''} (failed {self.failed}{eta})", err=True)

    def close(self):
        if self.bar is not None:
            self.bar.close()
            self.bar = None
