"""``python3 -m cutsim.batch MANIFEST --out DIR ...`` (the same as ``cutsim batch``), and the child
process of a regression comparison: ``python3 -m cutsim.batch --compare PART REFERENCE RESULT.json``
(cutsim.batch.job, run under the job's limits)."""
import sys

from .command import batch_command
from .job import compare_main

if len(sys.argv) == 5 and sys.argv[1] == "--compare":
    sys.exit(compare_main(sys.argv[2:]))
batch_command()
