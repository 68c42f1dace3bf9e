"""Trajectory readers and odometry metrics from Python, against evo's published numbers."""
import numpy as np
import pytest

import loopscan
from conftest import SHARED, skip_without_shared


def test_ape_and_rpe_match_evo_on_orb_slam2_kitti00():
    orb = SHARED / "data/real/evo-kitti00/KITTI_00_ORB.txt"
    gt_path = SHARED / "data/kitti/poses/00.txt"
    skip_without_shared(orb.exists() and gt_path.exists(), f"{orb} and {gt_path}")
    est, gt = loopscan.read_kitti_poses(str(orb)), loopscan.read_kitti_poses(str(gt_path))
    assert est.shape == gt.shape == (4541, 4, 4) and est.dtype == np.float64
    m = loopscan.odometry_metrics(gt, est)
    assert abs(m["ate_rmse_m"] - 1.3034) < 5e-5  # evo_ape --align
    assert m["segments"] > 0 and m["lengths_m"] == [100, 200, 300, 400, 500, 600, 700, 800]
    r = loopscan.relative_pose_error(gt, est[:, :3, :], delta_m=10.0)  # 3x4 works as well
    assert abs(r["translation_rmse_m"] - 0.2263) < 5e-5  # evo_rpe --delta 10 --delta_unit m


def test_a_constant_scale_drift_by_hand(tmp_path):
    n = 101
    gt = np.tile(np.eye(4), (n, 1, 1))
    gt[:, 2, 3] = np.arange(n, dtype=float)
    est = gt.copy()
    est[:, 2, 3] *= 1.01
    r = loopscan.relative_pose_error(gt, est, delta_m=10.0)
    assert r["pairs"] == 9 and abs(r["translation_rmse_m"] - 0.1) < 1e-9
    m = loopscan.odometry_metrics(gt, est, lengths_m=[50], step_frames=1)
    # KITTI's devkit: a segment ends at the first frame MORE than 50 m on (51 m here) and its
    # 0.51 m error is divided by the nominal 50 m: 1.02 %.
    assert abs(m["translation_percent"] - 1.02) < 1e-9
    # 1 % too long: the similarity alignment's scale undoes it, and nothing is left.
    assert abs(m["sim3_scale"] - 1 / 1.01) < 1e-12 and m["ate_sim3_rmse_m"] < 1e-9
    assert m["ate_rmse_m"] > 0.1
    with pytest.raises(ValueError, match=r"estimate: expected an array of shape \(N, 3, 4\)"):
        loopscan.odometry_metrics(gt, est[:, :2, :])
    with pytest.raises(ValueError):
        loopscan.relative_pose_error(gt, est[:-1], delta_m=10.0)
    # TUM round trip: times and poses as written.
    with open(tmp_path / "t.txt", "w") as f:
        f.write("# t x y z qx qy qz qw\n1.0 1 2 3 0 0 0 1\n2.5 4 5 6 0 0 0.7071067811865476 "
                "0.7071067811865476\n")
    times, T = loopscan.read_tum(str(tmp_path / "t.txt"))
    np.testing.assert_allclose(times, [1.0, 2.5])
    np.testing.assert_allclose(T[1][:3, 3], [4, 5, 6])
    np.testing.assert_allclose(T[1][:2, :2], [[0, -1], [1, 0]], atol=1e-12)  # 90 deg about z
