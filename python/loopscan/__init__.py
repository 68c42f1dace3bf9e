"""loopscan: fast, robust place recognition for stereo visual odometry (Mo & Sattar 2020).

The functions take and return numpy arrays: poses as (ids, T_cam_world (K, 3, 4)), VO points as
(ids, xyz_gray (N, 4)), signatures as (rows, values) float64 arrays, positions as (N, 3).
"""
from ._loopscan import (  # noqa: F401
    Candidate,
    Database,
    KeyframeClosure,
    KeyframeResult,
    Loop,
    LoopCloser,
    PlaceEvaluation,
    Recognizer,
    SequenceSignatures,
    SignatureSet,
    __version__,
    describe,
    describe_sequence,
    evaluate_places,
    odometry_metrics,
    read_kitti_poses,
    read_positions,
    read_signatures,
    read_sodso_points,
    read_sodso_poses,
    read_tum,
    relative_pose_error,
)

__all__ = [
    "Candidate", "Database", "KeyframeClosure", "KeyframeResult", "Loop", "LoopCloser", "PlaceEvaluation", "Recognizer", "SequenceSignatures", "SignatureSet", "__version__", "describe",
    "describe_sequence", "evaluate_places", "odometry_metrics", "read_kitti_poses",
    "read_positions", "read_signatures", "read_sodso_points", "read_sodso_poses", "read_tum",
    "relative_pose_error",
]
