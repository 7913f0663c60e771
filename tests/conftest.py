import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("CUTSIM_SHARED", ROOT.parent / "shared"))
EXAMPLES = SHARED / "examples"


@pytest.fixture(scope="session")
def examples() -> Path:
    if not EXAMPLES.is_dir():
        pytest.fail(f"../shared/examples not found at {EXAMPLES} (set CUTSIM_SHARED)")
    return EXAMPLES
