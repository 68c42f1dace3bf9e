#!/usr/bin/env python3
"""What the Python binding costs over the C++ calls, measured in one run on the k06 fixture:

- Recognizer.add_keyframe streamed over all 910 keyframes (default Scan Context), per keyframe,
  against loopscan_bench's BM_RecognizerStream (the same loop in C++);
- Database.query (indexed, k = 1) at 100k places (the fixture's 880 places, then copies of them
  with 10 % multiplicative noise), per query, against `loopscan db query` on the same saved file
  and the same 880 query signatures (the CLI times the C++ query call alone).

    PYTHONPATH=build/python python3 bench/python/bench_bindings.py [--places 100000] [--reps 5]
        [--write-docs]   (also writes the table into docs/performance.md, block python-bench)
Needs `cmake --build build --target benchmarks loopscan` and the fixture (LOOPSCAN_SHARED).
Prints medians and the ratios Python / C++.
"""
import argparse
import json
import os
import pathlib
import re
import statistics
import subprocess
import tempfile
import time

import numpy as np

import loopscan

REPO = pathlib.Path(__file__).resolve().parents[2]
SHARED = pathlib.Path(os.environ.get("LOOPSCAN_SHARED", REPO.parent / "shared"))
K06 = SHARED / "fixtures/k06-summer"
CLI = REPO / "build/apps/loopscan/loopscan"
BENCH = REPO / "build/bench/loopscan_bench"


def stream_ms(poses, points):
    (ids, T), (pid, xyzg) = poses, points
    ends = np.searchsorted(pid, ids, side="right")
    slices = [(int(k), T[i], xyzg[(ends[i - 1] if i else 0):ends[i]]) for i, k in enumerate(ids)]
    rec = loopscan.Recognizer(method="sc")
    t0 = time.perf_counter()
    for k, pose, pts in slices:
        rec.add_keyframe(k, pose, pts)
    return 1e3 * (time.perf_counter() - t0) / len(slices)


def cpp_stream_ms(reps):
    out = subprocess.run([str(BENCH), "--benchmark_filter=BM_RecognizerStream",
                          "--benchmark_format=json", f"--benchmark_repetitions={reps}",
                          "--benchmark_report_aggregates_only=true"],
                         check=True, capture_output=True, text=True).stdout
    runs = json.loads(out)["benchmarks"]
    return next(1e3 * b["per_item"] for b in runs if b.get("aggregate_name") == "median")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--places", type=int, default=100_000)
    parser.add_argument("--reps", type=int, default=5)
    parser.add_argument("--write-docs", action="store_true",
                        help="write the table into docs/performance.md (block python-bench)")
    args = parser.parse_args()
    poses = loopscan.read_sodso_poses(str(K06 / "poses_history_file.txt"))
    points = loopscan.read_sodso_points(str(K06 / "pts_history_file.txt.gz"))

    py_stream = statistics.median(stream_ms(poses, points) for _ in range(args.reps))
    cpp_stream = cpp_stream_ms(args.reps)

    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        subprocess.run([str(CLI), "describe", "--method", "sc", "--poses",
                        str(K06 / "poses_history_file.txt"), "--points",
                        str(K06 / "pts_history_file.txt.gz"), "--out", str(tmp / "q")],
                       check=True, capture_output=True)
        queries = loopscan.read_signatures(str(tmp / "q"), method="sc").signatures
        rng = np.random.default_rng(1)
        db = loopscan.Database(method="sc")
        for i in range(args.places):
            s = queries[i % len(queries)]
            if i >= len(queries):  # a perturbed copy; the intensity half stays binary
                s = s * (1 + 0.1 * rng.standard_normal(s.shape))
                s[:, s.shape[1] // 2:] = (s[:, s.shape[1] // 2:] > 0.5).astype(float)
            db.add(s[:1], keyframe=i)  # places keep row 0 (the place itself)
        db.save(str(tmp / "map.db"))
        db = loopscan.Database.load(str(tmp / "map.db"))
        py_query = []
        for _ in range(args.reps):
            t0 = time.perf_counter()
            for q in queries:
                db.query(q, k=1)
            py_query.append(1e3 * (time.perf_counter() - t0) / len(queries))
        cpp_query = []
        for _ in range(args.reps):
            out = subprocess.run([str(CLI), "db", "query", "--db", str(tmp / "map.db"),
                                  "--signatures", str(tmp / "q"), "--k", "1", "--out",
                                  str(tmp / "out")], check=True, capture_output=True, text=True)
            cpp_query.append(float(re.search(r"([0-9.]+) ms per query", out.stdout).group(1)))
    pq, cq = statistics.median(py_query), statistics.median(cpp_query)
    table = ("| call | Python (ms) | C++ (ms) | Python / C++ |\n| --- | --- | --- | --- |\n"
             f"| Recognizer.add_keyframe, k06, per keyframe | {py_stream:.3f} | {cpp_stream:.3f} "
             f"| {py_stream / cpp_stream:.3f} |\n"
             f"| Database.query indexed, {args.places} places, per query | {pq:.3f} | {cq:.3f} | "
             f"{pq / cq:.3f} |\n")
    print(table, end="")
    if args.write_docs:
        subprocess.run([str(REPO / "scripts/replace-doc-block"), "python-bench",
                        str(REPO / "docs/performance.md")], input=table, text=True, check=True)

if __name__ == "__main__":
    main()
