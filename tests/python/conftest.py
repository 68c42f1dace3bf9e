"""Shared paths for the Python tests (set by ctest; defaults for a run from the repository)."""
import os
import pathlib

import numpy as np
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
