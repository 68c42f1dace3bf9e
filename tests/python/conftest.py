"""Shared paths for the Python tests (set by ctest; defaults for a run from the repository)."""
import os
import pathlib

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
SHARED = pathlib.Path(os.environ.get("LOOPSCAN_SHARED", REPO.parent / "shared"))
CLI = os.environ.get("LOOPSCAN_CLI", str(REPO / "build/apps/loopscan/loopscan"))
K06 = SHARED / "fixtures/k06-summer"


@pytest.fixture
def k06():
    if not (K06 / "poses_history_file.txt").exists():
        pytest.skip(f"k06 fixture not found at {K06} (set LOOPSCAN_SHARED)")
    return K06
