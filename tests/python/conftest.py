"""Shared paths for the Python tests (set by ctest; defaults for a run from the repository)."""
import os
import pathlib

import numpy as np
import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
SHARED = pathlib.Path(os.environ.get("LOOPSCAN_SHARED", REPO.parent / "shared"))
CLI = os.environ.get("LOOPSCAN_CLI", str(REPO / "build/apps/loopscan/loopscan"))
K06 = SHARED / "fixtures/k06-summer"


def skip_without_shared(present, what):
    """Ends a test whose shared data is absent: skipped, or failed where LOOPSCAN_REQUIRE_SHARED=1
    (CI sets it, so that a missing reference file cannot leave CI green)."""
    if present:
        return
    if os.environ.get("LOOPSCAN_REQUIRE_SHARED", "") not in ("", "0"):
        pytest.fail(f"needs {what} (LOOPSCAN_REQUIRE_SHARED is set)")
    pytest.skip(f"needs {what} (set LOOPSCAN_SHARED to the shared/ folder)")


@pytest.fixture
def k06():
    skip_without_shared((K06 / "poses_history_file.txt").exists(), f"the k06 fixture at {K06}")
    return K06


def street(n_keyframes=60, points_per_keyframe=300, seed=3):
    """A straight drive along z past random boxes: poses and VO points as the readers return."""
    rng = np.random.default_rng(seed)
    ids = np.arange(n_keyframes, dtype=np.int32)
    T = np.zeros((n_keyframes, 3, 4))
    T[:, :, :3] = np.eye(3)
    T[:, 2, 3] = -1.0 * ids  # world-to-camera: the camera at z = id metres
    pid = np.repeat(ids, points_per_keyframe)
    xyz = rng.uniform([-20, -3, -5], [20, 1, 40], size=(pid.size, 3))
    xyz[:, 2] += pid  # points ahead of each keyframe
    gray = rng.uniform(0, 255, size=(pid.size, 1))
    return (ids, T), (pid, np.hstack([xyz, gray]))
