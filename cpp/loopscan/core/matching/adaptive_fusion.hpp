#pragma once
// Fusion that stays robust when one half of a signature is unreliable for a pair of sessions
// (gray values across seasons) and keeps the ranking of queries meaningful across queries.
//
// The paper fuses per query: D = w_s z_row(D_s) + z_row(D_i), each half z-scored over its own
// row. Two things go wrong across sessions: (1) a half that contradicts the other still gets
// its full weight; (2) per-row z-scores make every query's best match look equally good, so
// the ranking *across* queries (which decides recall at 100 % precision) follows how peaked a
// row is rather than how similar the places are. Adaptive fusion, for one pair of place sets:
// - each half's value is the mean of its row z-score (distinctiveness within the row) and its
//   global z-score (mean and deviation over every entry of the whole difference matrix:
//   similarity on one scale for all queries);
// - weights: how often the intensity half's best place is among the structure half's best k
//   (k = 1 % of the places, at least 1) measures how far the halves agree beyond chance,
//   r = (agreement - chance) / (1 - chance) clamped to [0, 1]; the half whose best matches
//   stand out more (mean -min z_row) keeps its full weight (structure w_s, intensity 1), the
//   other is scaled by r.
// It needs every query's row twice (statistics, then fusion): an offline evaluation.
#include <Eigen/Core>

namespace loopscan {

struct FusionWeights {
  double structure = 2.0, intensity = 1.0;
  double agreement = 0, chance = 0, reliability = 1;
  double structure_peak = 0, intensity_peak = 0;
  double structure_mean = 0, structure_std = 1, intensity_mean = 0, intensity_std = 1;
};

// Statistics of the first pass, one row at a time (rows in any order; merge per thread).
class FusionStatistics {
 public:
  // Raw structure / intensity distances of query `query` to every place; columns with
  // |query - j| < mask_width cannot be its match.
  void add_row(const Eigen::RowVectorXd& structure, const Eigen::RowVectorXd& intensity, int query,
               int mask_width);
  void merge(const FusionStatistics& other);
  FusionWeights weights(double structure_weight = 2.0) const;

 private:
  double sum_s_ = 0, sum_ss_ = 0, sum_i_ = 0, sum_ii_ = 0, entries_ = 0;
  double peak_s_ = 0, peak_i_ = 0, chance_sum_ = 0;
  int agree_ = 0, counted_ = 0;
};

// Pass two: the fused row of one query (raw halves as given to add_row).
Eigen::RowVectorXd adaptive_fused_row(const Eigen::RowVectorXd& structure,
                                      const Eigen::RowVectorXd& intensity,
                                      const FusionWeights& weights);

}  // namespace loopscan
