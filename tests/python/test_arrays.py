"""Shapes, dtypes and errors at the boundary; signatures of a synthetic drive (no shared data)."""
import numpy as np
import pytest

import loopscan
from conftest import street


def test_signature_shapes_per_method_and_mode():
    poses, points = street()
    for method, mode, rows, values in [("sc", "default", 5, 2400), ("sc", "reference", 1, 2400),
                                       ("m2dp", "default", 4, 384), ("delight", "default", 16, 256)]:
        s = loopscan.describe_sequence(poses, points, method=method, mode=mode)
        assert len(s) == 60 - 30  # the first INIT_FRAME keyframes only accumulate points
        assert s.keyframe_ids.dtype == np.int32 and s.keyframe_ids[0] == 30
        sig = s.signatures[0]
        assert sig.dtype == np.float64 and sig.ndim == 2
        assert sig.shape == (rows, values), (method, mode, sig.shape)


def test_inputs_are_converted_not_refused():
    (ids, T), (pid, xyzg) = street(40)
    a = loopscan.describe_sequence((ids, T), (pid, xyzg), method="delight")
    b = loopscan.describe_sequence((ids.astype(np.int64), T.astype(np.float32)),
                                   (pid.astype(np.int64), np.asfortranarray(xyzg)), method="delight")
    assert len(a) == len(b) == 10
    for x, y in zip(a.signatures, b.signatures):  # float32 poses round a little
        np.testing.assert_allclose(x, y, rtol=1e-3, atol=1e-3)


def test_bad_input_raises_with_the_reason():
    poses, points = street(40)
    with pytest.raises(ValueError, match=r"points: expected an array of shape \(N, 4\)"):
        loopscan.describe(np.zeros((5, 3)))
    with pytest.raises(ValueError, match=r"T_cam_world: expected an array of shape \(40, 3, 4\)"):
        loopscan.describe_sequence((poses[0], poses[1][:, :2]), points)
    with pytest.raises(ValueError, match=r"unknown mode 'fast' \(expected reference or default\)"):
        loopscan.describe_sequence(poses, points, mode="fast")
    with pytest.raises(ValueError, match=r"unknown method .sift. \(expected sc, m2dp, delight or bev\)"):
        loopscan.describe_sequence(poses, points, method="sift")
    with pytest.raises(ValueError, match="keyframe ids in increasing order"):
        loopscan.describe_sequence((poses[0][::-1].copy(), poses[1]), points)
    with pytest.raises(ValueError, match="point ids in non-decreasing order"):
        loopscan.describe_sequence(poses, (points[0][::-1].copy(), points[1]))
    with pytest.raises(ValueError, match="expected .* tuples"):
        loopscan.describe_sequence(poses[0], points)
    with pytest.raises(ValueError, match="protocol: expected 'same'"):
        loopscan.evaluate_places([], [], np.zeros((0, 3)), np.zeros((0, 3)), protocol="both")
    with pytest.raises(RuntimeError, match="/nonexistent/poses.txt"):
        loopscan.read_sodso_poses("/nonexistent/poses.txt")


def test_read_write_round_trip_and_repr(tmp_path):
    (ids, T), (pid, xyzg) = street(35, 20)
    with open(tmp_path / "poses.txt", "w") as f:
        for i, t in zip(ids, T):
            f.write(f"{i} " + " ".join(f"{v:.9g}" for v in t.ravel()) + "\n")
    with open(tmp_path / "pts.txt", "w") as f:
        for i, p in zip(pid, xyzg):
            f.write(f"{i} {p[0]:.4f} {p[1]:.4f} {p[2]:.4f} {p[3]:.1f}\n")
    rids, rT = loopscan.read_sodso_poses(str(tmp_path / "poses.txt"))
    np.testing.assert_array_equal(rids, ids)
    np.testing.assert_allclose(rT, T, atol=1e-9)
    pids, pxyz = loopscan.read_sodso_points(str(tmp_path / "pts.txt"))
    np.testing.assert_array_equal(pids, pid)
    rounded = np.hstack([np.round(xyzg[:, :3], 4), np.round(xyzg[:, 3:], 1)])
    np.testing.assert_allclose(pxyz, rounded, atol=1e-4)
    s = loopscan.describe_sequence((rids, rT), (pids, pxyz))
    assert repr(s).startswith("<SequenceSignatures: 5 places")
    assert loopscan.__version__.count(".") == 2
