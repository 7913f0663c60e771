"""``cutsim batch``: verify many part programs at once, on a local pool or on a Dask cluster.

Each job runs the public command ``python3 -m cutsim simulate PROGRAM --setup S --out TMP
[--tolerance T] [--images] -q`` in its own process with a time limit and an address-space limit
(RLIMIT_AS); a crash, a time-out or an out-of-memory is that job's result. The job writes into a
private temporary directory where it runs; its files come back to the caller, which commits them
into ``DIR/<job>/`` with cutsim's own output transaction -- so the results are the same bytes
whichever scheduler ran the jobs, and a Dask worker needs no write access to DIR. The user docs
are docs/batch.md.

From Python: ``cutsim.batch.run_batch(jobs, out=None, client=None, **options)``.

The modules, one job each: ``manifest`` (the jobs of a TOML/CSV manifest or a folder), ``keys``
(resume keys), ``process`` (running a command under limits, stopping it), ``job`` (one job where
it runs), ``records`` (a job's status and record), ``schedule`` (local pool or Dask), ``progress``,
``run`` (the batch and its outputs), ``junit`` and ``index`` (junit.xml, index.html from
``templates/index.html.j2``), ``command`` (the click command).
"""
from __future__ import annotations

from .command import batch_command
from .index import index_html
from .job import compare_solids, run_job
from .junit import junit_xml
from .keys import code_key, job_key, referenced_files
from .manifest import Job, load_manifest
from .records import DEFAULT_REFERENCE_TOL, ERROR_STATUSES, FAILED, PASSED
from .run import DEFAULT_MEMORY, DEFAULT_TIMEOUT, BatchSummary, run_batch

__all__ = ["BatchSummary", "DEFAULT_MEMORY", "DEFAULT_REFERENCE_TOL", "DEFAULT_TIMEOUT", "ERROR_STATUSES", "FAILED",
           "Job", "PASSED", "batch_command", "code_key", "compare_solids", "index_html", "job_key", "junit_xml",
           "load_manifest", "referenced_files", "run_batch", "run_job"]
