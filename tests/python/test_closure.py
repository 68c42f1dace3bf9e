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


def test_background_closer_gives_the_synchronous_loops_and_releases_the_gil():
    import threading
    (ids, T), (pid, xyzg) = loop_drive(130)
    sync = loopscan.LoopCloser(method="sc")
    background = loopscan.BackgroundLoopCloser(method="sc", queue_capacity=4, when_full="wait",
                                               threads=2)  # its alignments on 2 threads
    ticks = []
    stop = threading.Event()
    # A Python thread keeps running while the worker verifies: add_keyframe, poll and finish
    # release the GIL.
    ticker = threading.Thread(target=lambda: [ticks.append(1) or stop.wait(0.001)
                                              for _ in iter(lambda: stop.is_set(), True)])
    ticker.start()
    closures = []
    for i, kf in enumerate(ids):
        points = xyzg[pid == kf]
        sync.add_keyframe(int(kf), T[i], points)
        r = background.add_keyframe(int(kf), T[i], points)
        assert r.keyframe == kf and r.verified == []  # verification comes later
        closures += background.poll()
        seen_ids, seen_T = background.corrected_poses()
        np.testing.assert_array_equal(seen_ids, ids[:i + 1])  # every keyframe given so far
    sync.finish()
    background.finish()
    stop.set()
    ticker.join()
    closures += background.poll()
    assert [c.keyframe for c in closures] == list(ids)
    assert sum(len(c.accepted) for c in closures) >= 10
    assert [(l.query, l.match_keyframe, l.verdict) for l in background.loops] == \
        [(l.query, l.match_keyframe, l.verdict) for l in sync.loops]
    np.testing.assert_array_equal(background.corrected_poses()[1], sync.corrected_poses()[1])
    assert background.queue["waiting"] == 0 and background.queue["skipped"] == 0
    assert len(ticks) > 10
    with pytest.raises(ValueError, match="when_full: expected 'skip' or 'wait'"):
        loopscan.BackgroundLoopCloser(when_full="drop")
    with pytest.raises(ValueError, match="threads: expected 1 to 256, got 0"):
        loopscan.LoopCloser(threads=0)
