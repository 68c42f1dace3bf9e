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
//   r = (agreement - chance) / (1 - chance) clamped to [0, 1]; the leading half keeps its full
//   weight (structure w_s, intensity 1), the other is scaled by r, or dropped when r < 0.1:
//   then the leading half alone ranks the places, exactly as `--fusion structure` or
//   `intensity` would;
// - the leading half is the one whose best matches stand out more (mean -min z_row), unless
//   its best matches follow the drive markedly less than the other half's. Queries are
//   consecutive keyframes, so a half that recognises places moves its best match along the map
//   as the query moves, while a half without signal jumps, or sticks to a few "hub" places
//   that are best for many queries, which also makes it stand out: a descriptor collapsed
//   across seasons can be the more peaked half. Each half's sequence reliability is the share
//   of consecutive queries whose best places are within 5 places of each other, above the
//   share for two random queries (which counts hubs), scaled like r; the peak's half gives way
//   when its reliability is below half the other's. With fewer than 20 consecutive queries the
//   peak decides alone.
// It needs every query's row twice (statistics, then fusion): an offline evaluation.
#include <vector>

#include <Eigen/Core>

namespace loopscan {

struct FusionWeights {
  double structure = 2.0, intensity = 1.0;
  double agreement = 0, chance = 0, reliability = 1;
  double structure_peak = 0, intensity_peak = 0;
  // Sequence reliabilities in [-1, 1] (0: chance; NaN: too few consecutive queries).
  double structure_sequence = 0, intensity_sequence = 0;
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
  struct Best {
    int query, structure, intensity;
  };
  std::vector<Best> bests_;
};

// Pass two: the fused row of one query (raw halves as given to add_row).
Eigen::RowVectorXd adaptive_fused_row(const Eigen::RowVectorXd& structure,
                                      const Eigen::RowVectorXd& intensity,
                                      const FusionWeights& weights);

}  // namespace loopscan
