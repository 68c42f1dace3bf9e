#include "loopscan/eval/latency.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace loopscan::eval {

double percentile(std::vector<double> samples, double p) {
  if (!(p > 0 && p <= 1)) throw std::invalid_argument("percentile: p must be in (0, 1]");
  if (samples.empty()) return 0;
  // Rank ceil(p n), 1-based; the small tolerance keeps p n that is an integer from rounding up.
  const double rank = std::ceil(p * static_cast<double>(samples.size()) - 1e-9);
  const auto k = static_cast<std::size_t>(std::max(rank, 1.0)) - 1;
  std::nth_element(samples.begin(), samples.begin() + static_cast<std::ptrdiff_t>(k),
                   samples.end());
  return samples[k];
}

LatencySummary summarise_latency(const std::vector<double>& ms) {
  LatencySummary s;
  s.count = static_cast<int>(ms.size());
  if (ms.empty()) return s;
  s.p50_ms = percentile(ms, 0.50);
  s.p99_ms = percentile(ms, 0.99);
  s.max_ms = *std::max_element(ms.begin(), ms.end());
  return s;
}

}  // namespace loopscan::eval
