#pragma once
// The image baselines under the evaluation protocol: the best database place of every query
// (GIST by Euclidean distance, exhaustive; BoW by the L1 score through the inverted index), with
// the same-session index mask |i - j| >= mask (0 across sessions). BoW distances are
// 1 - score, so that smaller is better for every method.
#include <vector>

#include <Eigen/Core>

#include "loopscan/baselines/vocabulary.hpp"
#include "loopscan/eval/best_match.hpp"

namespace loopscan::baselines {

struct BaselineMatches {
  std::vector<eval::QueryMatch> matches;  // one per query; match -1 / +inf when none allowed
  double query_ms = 0;                    // mean per query, one thread
};

BaselineMatches best_gist_matches(const std::vector<Eigen::VectorXf>& queries,
                                  const std::vector<Eigen::VectorXf>& database, int mask);

BaselineMatches best_bow_matches(const std::vector<BowVector>& queries,
                                 const std::vector<BowVector>& database, int mask);

}  // namespace loopscan::baselines
