#pragma once
// Latency of a per-item call (a keyframe into the loop closer): the median, the 99th percentile
// and the worst, as a live system's budget is stated.
#include <vector>

namespace loopscan::eval {

struct LatencySummary {
  int count = 0;
  double p50_ms = 0, p99_ms = 0, max_ms = 0;  // 0 without samples
};

// Nearest-rank percentile: the smallest sample with at least fraction p of the samples at or
// below it (p in (0, 1]). Empty -> 0.
double percentile(std::vector<double> samples, double p);

LatencySummary summarise_latency(const std::vector<double>& ms);

}  // namespace loopscan::eval
