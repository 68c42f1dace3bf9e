"""loopscan: fast, robust place recognition for stereo visual odometry (Mo & Sattar 2020).

numpy in and out: poses as (ids, T_cam_world (K, 3, 4)), VO points as (ids, xyz_gray (N, 4)),
signatures as (rows, values) float64 arrays, positions as (N, 3), images as (H, W) uint8.
Errors come back as ValueError (bad arguments, with what was expected) or RuntimeError (bad
files: file, line and what was expected).
"""
from ._loopscan import (  # noqa: F401
    BackgroundLoopCloser,
    Candidate,
    Database,
    FrameResult,
    KeyframeClosure,
    KeyframeResult,
    Loop,
    LoopCloser,
    PlaceEvaluation,
    Recognizer,
    SequenceSignatures,
    SignatureSet,
    StereoVo,
    __version__,
    describe,
    describe_sequence,
    evaluate_places,
    odometry_metrics,
    read_gray_image,
    read_kitti_calib,
    read_kitti_poses,
    read_positions,
    read_signatures,
    read_sodso_points,
    read_sodso_poses,
    read_tum,
    relative_pose_error,
)

__all__ = [name for name in dir() if not name.startswith("_")] + ["__version__"]
