#!/usr/bin/env python3
"""Stream a VO export (SO-DSO files) through loopscan's Recognizer, keyframe by keyframe as a
live VO would, then plot the trajectory with the recognised loops and the precision-recall
curve of the streamed matches against the ground truth.

    python3 stream_recognizer.py --dir ../shared/fixtures/k06-summer --out out/stream
    (DIR holds poses_history_file.txt, pts_history_file.txt[.gz] and gt.txt, KITTI poses)

Writes OUT/trajectory.png, OUT/pr.png and OUT/map.db (the places, for query_saved_db.py).
"""
import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")  # files only, no display needed
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import loopscan  # noqa: E402


def stream(poses, points):
    """Feeds the keyframes in order; returns (keyframe, best match or None) per described place."""
    (ids, T), (pid, xyzg) = poses, points
    starts = np.searchsorted(pid, ids, side="right")  # points are sorted by keyframe id
    rec = loopscan.Recognizer(method="sc")
    results, first = [], 0
    for i, kf in enumerate(ids):
        for r in rec.add_keyframe(int(kf), T[i], xyzg[first:starts[i]]):
            results.append((r.keyframe, r.matches[0] if r.matches else None))
        first = starts[i]
    results += [(r.keyframe, r.matches[0] if r.matches else None) for r in rec.finish()]
    return rec, results


def pr_curve(results, gt, threshold_m=10.0):
    """Precision and recall of the streamed top-1 matches, ranked by their distance."""
    matched = [(m.distance, kf, m.keyframe) for kf, m in results if m is not None]
    matched.sort()
    true = np.array([np.linalg.norm(gt[q] - gt[p]) < threshold_m for _, q, p in matched])
    described = [kf for kf, _ in results]
    # A revisit: an earlier place (before the 99 the recognizer skips) within the threshold.
    revisits = sum(
        any(np.linalg.norm(gt[q] - gt[p]) < threshold_m for p in described[:max(0, k - 99)])
        for k, q in enumerate(described))
    tp = np.cumsum(true)
    precision = tp / np.arange(1, len(true) + 1)
    recall = tp / max(revisits, 1)
    return precision, recall, matched, true


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dir", required=True, help="SO-DSO export with gt.txt")
    parser.add_argument("--out", default="out/stream", help="output directory")
    args = parser.parse_args()
    d, out = pathlib.Path(args.dir), pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    points_file = next(p for p in (d / "pts_history_file.txt.gz", d / "pts_history_file.txt")
                       if p.exists())
    poses = loopscan.read_sodso_poses(str(d / "poses_history_file.txt"))
    points = loopscan.read_sodso_points(str(points_file))
    gt = loopscan.read_positions(str(d / "gt.txt"))

    rec, results = stream(poses, points)
    rec.database.save(str(out / "map.db"))
    precision, recall, matched, true = pr_curve(results, gt)
    full = recall[precision == 1.0].max(initial=0.0)
    print(f"{len(results)} places, {len(matched)} matched; recall at 100 % precision {full:.3f}")

    # Trajectory (x, z) with the loops recognised at 100 % precision.
    accepted = matched[:int(np.argmin(true)) if not true.all() else len(true)]
    fig, ax = plt.subplots(figsize=(7, 6))
    ax.plot(gt[:, 0], gt[:, 2], color="0.7", lw=2, label="ground truth")
    for _, q, p in accepted:
        ax.plot([gt[q, 0], gt[p, 0]], [gt[q, 2], gt[p, 2]], color="tab:orange", lw=0.8)
    ax.scatter(gt[[q for _, q, _ in accepted], 0], gt[[q for _, q, _ in accepted], 2], s=8,
               color="tab:red", label=f"recognised at 100 % precision ({len(accepted)})")
    ax.set(xlabel="x [m]", ylabel="z [m]", title="Places recognised while streaming")
    ax.set_aspect("equal", adjustable="datalim")  # true shape, the figure filled
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=2)
    fig.savefig(out / "trajectory.png", dpi=120, bbox_inches="tight")

    fig, ax = plt.subplots(figsize=(6, 5))
    ax.plot(recall, precision, color="tab:blue")
    ax.set(xlabel="recall", ylabel="precision", xlim=(-0.02, 1.02), ylim=(-0.02, 1.02),
           title=f"Streamed Scan Context matches (recall@100%P {full:.3f})")
    ax.grid(alpha=0.3)
    fig.savefig(out / "pr.png", dpi=120, bbox_inches="tight")
    print(f"-> {out}/trajectory.png, {out}/pr.png, {out}/map.db")


if __name__ == "__main__":
    main()
