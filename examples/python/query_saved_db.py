#!/usr/bin/env python3
"""Query a database saved by another session (stream_recognizer.py writes OUT/map.db): describe
a VO export and ask the map, place by place, where it is.

    python3 query_saved_db.py --db out/stream/map.db --dir ../shared/fixtures/k06-summer
"""
import argparse
import pathlib

import numpy as np

import loopscan


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--db", required=True, help="a database file (Database.save, db build)")
    parser.add_argument("--dir", required=True, help="SO-DSO export to query with")
    parser.add_argument("--k", type=int, default=1, help="candidates per query")
    args = parser.parse_args()
    d = pathlib.Path(args.dir)
    points_file = next(p for p in (d / "pts_history_file.txt.gz", d / "pts_history_file.txt")
                       if p.exists())
    db = loopscan.Database.load(args.db)
    sigs = loopscan.describe_sequence(loopscan.read_sodso_poses(str(d / "poses_history_file.txt")),
                                      loopscan.read_sodso_points(str(points_file)),
                                      method=db.method)
    found = [db.query(s, k=args.k, retrieval="exact") for s in sigs.signatures]
    same = np.mean([bool(f) and f[0].keyframe == kf for f, kf in zip(found, sigs.keyframe_ids)])
    print(f"{db}: {len(sigs)} queries; top-1 is the same keyframe for {100 * same:.1f} %")
    for kf, f in list(zip(sigs.keyframe_ids, found))[:3]:
        print(f"  keyframe {kf}: {f}")


if __name__ == "__main__":
    main()
