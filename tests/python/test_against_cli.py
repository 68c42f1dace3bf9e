"""The Python API computes what the CLI computes, on the real SO-DSO k06 fixture."""
import json
import subprocess

import numpy as np

import loopscan
from conftest import CLI


def run_cli(*args):
    subprocess.run([CLI, *map(str, args)], check=True, capture_output=True)


def test_describe_and_evaluate_equal_the_cli(k06, tmp_path):
    run_cli("describe", "--method", "sc", "--poses", k06 / "poses_history_file.txt",
            "--points", k06 / "pts_history_file.txt.gz", "--out", tmp_path / "sc")
    run_cli("evaluate", "--method", "sc", "--signatures", tmp_path / "sc", "--gt", k06 / "gt.txt",
            "--out", tmp_path / "eval")
    cli = json.loads((tmp_path / "eval/metrics.json").read_text())

    poses = loopscan.read_sodso_poses(str(k06 / "poses_history_file.txt"))
    points = loopscan.read_sodso_points(str(k06 / "pts_history_file.txt.gz"))
    ours = loopscan.describe_sequence(poses, points, method="sc")
    written = loopscan.read_signatures(str(tmp_path / "sc"), method="sc", gt=str(k06 / "gt.txt"))
    np.testing.assert_array_equal(ours.keyframe_ids, written.keyframe_ids)
    assert len(ours) == len(written) == cli["n_queries"]
    # The descriptor frames Database.add needs for the yaw: those `describe` wrote.
    assert ours.frames.shape == written.frames.shape == (len(ours), 3, 3)
    np.testing.assert_allclose(ours.frames, written.frames, atol=1e-6)
    for a, b in zip(ours.signatures, written.signatures):  # signatures.txt keeps 10 digits
        assert a.shape == b.shape
        assert np.max(np.abs(a - b)) <= 1e-9 * max(1.0, np.max(np.abs(a)))

    # Evaluating the written signatures reproduces the CLI's metrics to 1e-9.
    ev = loopscan.evaluate_places(written.signatures, written.signatures, written.positions,
                                  written.positions, method="sc")
    for key in ("auc", "recall_at_100_precision", "f1_max"):
        assert abs(getattr(ev, key) - cli[key]) <= 1e-9, key
    assert ev.n_gt_loops == cli["n_gt_loops"]
    # The in-memory signatures and the file's ground truth give the same metrics.
    gt = loopscan.read_positions(str(k06 / "gt.txt"))
    pos = gt[ours.keyframe_ids]
    direct = loopscan.evaluate_places(ours.signatures, ours.signatures, pos, pos, method="sc")
    assert abs(direct.auc - cli["auc"]) < 1e-4
    # The PR arrays are the curve the metrics come from.
    assert ev.precision.shape == ev.recall.shape == (cli["n_queries"],)
    assert ev.recall[-1] <= 1.0 and np.all(np.diff(ev.recall) >= 0)
