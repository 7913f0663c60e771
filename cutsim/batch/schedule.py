"""Scheduling: the jobs still to run on a local pool of threads (each supervising one job process)
or on a Dask cluster (``dask.distributed``: its scheduling, retries after a lost worker and
transport). Each finished job's raw outcome goes to ``done(item, raw)`` as it arrives.
"""
from __future__ import annotations

import uuid

from cutsim.interp.errors import CutsimError

from . import process
from .job import run_job


def run_local(todo, n, done, bar):
    """Run ``todo`` (items whose last element is the job's payload) on ``n`` threads. Ctrl-C stops
    every job process; the jobs that finished are still handed to ``done``."""
    from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait

    def work(item):
        bar.started()
        try:
            return run_job(item[3])
        finally:
            bar.stopped()

    ex = ThreadPoolExecutor(max_workers=max(1, n), thread_name_prefix="cutsim-batch")
    futs = {ex.submit(work, it): it for it in todo}
    try:
        pending = set(futs)
        while pending:
            ready, pending = wait(pending, timeout=0.5, return_when=FIRST_COMPLETED)
            for f in ready:
                done(futs[f], f.result())
    except KeyboardInterrupt:
        for f in futs:
            f.cancel()
        process.terminate_all()
        ex.shutdown(wait=True, cancel_futures=True)
        for f in futs:  # the jobs that were running end as "interrupted"; finished ones are kept
            if not f.cancelled() and f.done() and futs[f][0].name not in bar.seen:
                try:
                    done(futs[f], f.result())
                except Exception:  # noqa: BLE001
                    pass
        raise
    finally:
        ex.shutdown(wait=True, cancel_futures=True)


def run_dask(todo, client, scheduler, done, bar) -> str:
    """Run ``todo`` on a Dask cluster: ``client``, or a client of its own connected to
    ``scheduler``. A lost worker or a cancelled task is that job's internal error. Returns the
    scheduler's name for timings.json (``dask:ADDRESS``)."""
    from distributed import Client, as_completed

    own = client is None
    if own:
        try:
            client = Client(scheduler, timeout="30s")
        except Exception as e:  # noqa: BLE001 - an unreachable scheduler is an environment error
            raise CutsimError("cutsim", 0, 0, f"--scheduler: cannot connect to {scheduler}: {e}") from None
    try:
        try:
            nthreads = sum(client.nthreads().values()) or 1
        except Exception:  # noqa: BLE001
            nthreads = 1
        bar.slots = nthreads
        futs = {}
        for it in todo:
            f = client.submit(run_job, it[3], key=f"cutsim-job-{it[0].name}-{uuid.uuid4().hex[:8]}", pure=False)
            futs[f] = it
        try:
            for f in as_completed(list(futs)):
                try:
                    raw = f.result()
                except Exception as e:  # noqa: BLE001 - a lost worker (KilledWorker), a cancelled task
                    raw = {"exit": None, "signal": None, "stderr": f"batch: {type(e).__name__}: {e}",
                           "timed_out": False, "seconds": 0.0, "files": {}, "host": None, "internal": True}
                done(futs[f], raw)
                f.release()
        except KeyboardInterrupt:
            client.cancel(list(futs))
            raise
        return f"dask:{client.scheduler.address}"
    finally:
        if own:
            client.close()
