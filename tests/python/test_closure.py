"""The loop closer from Python: loops with a 4x4 relative pose, corrected poses."""
import numpy as np
import pytest

import loopscan
from test_database import loop_drive


def test_second_lap_closes_with_the_relative_pose_of_the_drive():
    # Laps of 130 keyframes: twins lie beyond the 99 places the recognition skips.
    (ids, T), (pid, xyzg) = loop_drive(130)
    closer = loopscan.LoopCloser(method="sc")
    accepted = []
    for i, kf in enumerate(ids):
        r = closer.add_keyframe(int(kf), T[i], xyzg[pid == kf])
        assert r.keyframe == kf
        accepted += r.accepted
    closer.finish()
    assert len(accepted) >= 10
    for loop in accepted:
        assert loop.accepted and loop.verdict == "accepted"
        assert loop.match_keyframe < 130 <= loop.query  # second lap onto the first
        # Camera k sits at z = k mod 130 in both laps, which saw the same points: the match's
        # camera frame maps into the query's by the shift between them along z.
        expected = np.eye(4)
        expected[2, 3] = loop.match_keyframe % 130 - loop.query % 130
        assert loop.T_query_match.shape == (4, 4)
        np.testing.assert_allclose(loop.T_query_match, expected, atol=0.1)
    assert "keyframe" in repr(accepted[0])
    cids, cT = closer.corrected_poses()
    np.testing.assert_array_equal(cids, ids)
    assert cT.shape == (len(ids), 3, 4)
    assert len(closer.loops) >= len(accepted)
    with pytest.raises(ValueError, match=r"T_cam_world: expected an array of shape \(3, 4\)"):
        closer.add_keyframe(999, np.eye(4), xyzg[:5])
