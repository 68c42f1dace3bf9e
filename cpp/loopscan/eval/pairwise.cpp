#include "loopscan/eval/pairwise.hpp"

#include <algorithm>
#include <cmath>

namespace loopscan::eval {

PairwiseResult evaluate_pairwise(std::vector<ScoreLabel> pairs) {
  // NaN has no place in a threshold sweep; sklearn would reject it.
  pairs.erase(std::remove_if(pairs.begin(), pairs.end(),
                             [](const ScoreLabel& p) { return std::isnan(p.score); }),
              pairs.end());
  PairwiseResult result;
  result.n_total = pairs.size();
  result.n_positive = static_cast<std::size_t>(
      std::count_if(pairs.begin(), pairs.end(), [](const ScoreLabel& p) { return p.label == 1; }));
  if (result.n_positive == 0) return result;

  std::sort(pairs.begin(), pairs.end(),
            [](const ScoreLabel& a, const ScoreLabel& b) { return a.score > b.score; });
  const double n_pos = static_cast<double>(result.n_positive);
  std::size_t tp = 0;
  std::size_t fp = 0;
  double prev_recall = 0.0;
  double prev_precision = 1.0;
  for (std::size_t i = 0; i < pairs.size();) {
    // All pairs sharing a score switch to positive at the same threshold.
    const double threshold = pairs[i].score;
    for (; i < pairs.size() && pairs[i].score == threshold; ++i) {
      if (pairs[i].label == 1) {
        ++tp;
      } else {
        ++fp;
      }
    }
    const double precision = static_cast<double>(tp) / static_cast<double>(tp + fp);
    const double recall = static_cast<double>(tp) / n_pos;
    result.curve.push_back({precision, recall});
    result.thresholds.push_back(threshold);

    result.average_precision += (recall - prev_recall) * precision;
    result.auc_trapezoid += (recall - prev_recall) * (precision + prev_precision) / 2.0;
    const double sum = precision + recall;
    const double f1 = sum > 0.0 ? 2.0 * precision * recall / sum : 0.0;
    if (f1 > result.f1_max) {
      result.f1_max = f1;
      result.best_threshold = threshold;
    }
    prev_recall = recall;
    prev_precision = precision;
  }
  return result;
}

}  // namespace loopscan::eval
