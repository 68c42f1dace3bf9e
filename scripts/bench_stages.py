"""loopscan_bench's JSON as per-stage milliseconds, shared by scripts/docs-speed and
scripts/bench-authors so both tables read the same benchmarks under the same labels."""
import json
import re
import sys

# (label, key of the authors' harness, the paper's printed ms, default-mode benchmarks,
#  reference-mode benchmarks). mode:0 = reference, mode:1 = default; filter:0 = Cartesian,
# filter:1 = polar. Reference imitation has no single benchmark: local map + crop, plus the
# reference filter.
STAGES = [
    ("imitation, Cartesian (local map + crop + voxel filter)", "imitation_cartesian", "1.8",
     ["BM_ImitateFast/filter:0"], ["BM_ImitateCrop/mode:0", "BM_Filter/mode:0/filter:0"]),
    ("imitation, polar (local map + crop + 1° filter)", "imitation_polar", "2.7",
     ["BM_ImitateFast/filter:1"], ["BM_ImitateCrop/mode:0", "BM_Filter/mode:0/filter:1"]),
    ("Scan Context descriptor (default: the place + 4 lateral versions)", "scan_context", "2.7",
     ["BM_Describe/method:0/mode:1"], ["BM_Describe/method:0/mode:0"]),
    ("M2DP descriptor (PCA + 4 versions)", "m2dp", "86",
     ["BM_Describe/method:1/mode:1"], ["BM_Describe/method:1/mode:0"]),
    ("DELIGHT descriptor", "delight", "3.7",
     ["BM_Describe/method:2/mode:1"], ["BM_Describe/method:2/mode:0"]),
]


def medians(path):
    """Benchmark name (without /iterations:N) -> median milliseconds per item."""
    out = {}
    for b in json.load(open(path))["benchmarks"]:
        if b.get("aggregate_name") == "median" and "per_item" in b:
            out[re.sub(r"/iterations:\d+", "", b["run_name"])] = 1e3 * b["per_item"]
    return out


def total(table, names, script):
    """Sum of the named benchmarks; exits naming the first one missing."""
    missing = [n for n in names if n not in table]
    if missing:
        sys.exit(f"{script}: benchmark {missing[0]} missing from loopscan_bench's output")
    return sum(table[n] for n in names)


def ms(x):
    return f"{x:.3g}" if x < 100 else f"{x:.0f}"
