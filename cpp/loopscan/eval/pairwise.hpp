#pragma once
// Pairwise evaluation in the scikit-learn precision_recall_curve convention, used to compare
// with published numbers of other detectors (higher score = more similar, label 1 = positive).
#include <cstddef>
#include <vector>

#include "loopscan/eval/precision_recall.hpp"

namespace loopscan::eval {

struct ScoreLabel {
  double score = 0.0;
  int label = 0;  // 1 = positive, anything else negative
};

struct PairwiseResult {
  std::vector<PrPoint> curve;      // one point per threshold, recall non-decreasing
  std::vector<double> thresholds;  // each distinct score, descending (sklearn: ascending)
  double f1_max = 0.0;
  double best_threshold = 0.0;     // highest threshold reaching f1_max
  double average_precision = 0.0;  // sum (R_k - R_{k-1}) P_k with R_0 = 0
  double auc_trapezoid = 0.0;      // trapezoid from (recall 0, precision 1), as sklearn's auc()
  std::size_t n_positive = 0;
  std::size_t n_total = 0;  // pairs evaluated (NaN scores are dropped)
};

// At threshold t a pair is predicted positive if score >= t; precision = TP/(TP+FP),
// recall = TP/P. With no positives recall is undefined: curve empty, metrics 0.
PairwiseResult evaluate_pairwise(std::vector<ScoreLabel> pairs);

}  // namespace loopscan::eval
