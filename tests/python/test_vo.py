"""Stereo VO from Python on real KITTI frames: the CLI's trajectory, frame by frame."""
import subprocess

import numpy as np
import pytest

import loopscan
from conftest import CLI, SHARED, skip_without_shared

KITTI = SHARED / "data/real/kitti06-000000-000050"


def test_vo_on_real_kitti_frames_equals_the_cli(tmp_path):
    skip_without_shared((KITTI / "calib.txt").exists(), f"the real KITTI frames at {KITTI}")
    subprocess.run([CLI, "vo", "--kitti", str(KITTI), "--out", str(tmp_path / "vo"), "--quiet"],
                   check=True, capture_output=True)
    cli = loopscan.read_kitti_poses(str(tmp_path / "vo/trajectory.txt"))

    calib = loopscan.read_kitti_calib(str(KITTI / "calib.txt"))
    left0 = loopscan.read_gray_image(str(KITTI / "image_0/000000.png"))
    assert left0.dtype == np.uint8 and left0.ndim == 2
    vo = loopscan.StereoVo(**calib, width=left0.shape[1], height=left0.shape[0])
    keyframes = 0
    for f in range(len(cli)):
        left = loopscan.read_gray_image(str(KITTI / f"image_0/{f:06d}.png"))
        right = loopscan.read_gray_image(str(KITTI / f"image_1/{f:06d}.png"))
        r = vo.process(f, left, right)
        assert r.frame == f and r.T_world_cam.shape == (4, 4)
        keyframes += r.keyframe
    vo.finish()
    np.testing.assert_allclose(vo.trajectory(), cli, atol=1e-6)
    kfs = vo.keyframes()
    assert len(kfs) == keyframes > 5
    frame, T, reset, points = kfs[1]
    assert T.shape == (4, 4) and points.shape[1] == 4 and len(points) > 100
    with pytest.raises(ValueError, match="implausible camera: expected a positive image size"):
        loopscan.StereoVo(**{**calib, "fx": 0.0}, width=1226, height=370)
    with pytest.raises(ValueError, match=r"left: expected an array of shape \(370, 1226\)"):
        vo.process(len(cli), left0[:100], left0)
