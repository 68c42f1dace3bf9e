#include "loopscan/core/matching/adaptive_fusion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "loopscan/core/matching/fusion.hpp"

namespace loopscan {
namespace {

// Index of the smallest allowed entry of a row (-1 when every column is excluded).
int allowed_argmin(const Eigen::RowVectorXd& row, int query, int mask_width) {
  int best = -1;
  for (int j = 0; j < row.size(); ++j) {
    if (std::abs(query - j) < mask_width) continue;
    if (best < 0 || row[j] < row[best]) best = j;
  }
  return best;
}

double deviation(double sum, double sum_sq, double n) {
  const double var = n > 1 ? (sum_sq - sum * sum / n) / (n - 1) : 0.0;
  return var > 0 ? std::sqrt(var) : 1.0;
}

// How far apart two best places may be and still follow one another: consecutive keyframes of
// two drives advance their matches by 0-3 places.
constexpr int kFollowWindow = 5;
constexpr int kMinConsecutive = 20;
// The leader gives way when its sequence reliability is below this share of the other half's.
constexpr double kSwitchShare = 0.5;
// Halves that agree less than this beyond chance are not fused: the leader alone decides.
constexpr double kDropReliability = 0.1;

// Consistency of consecutive queries' best places above the chance that two random queries'
// best places are as close, (consistent - chance) / (1 - chance); NaN without enough pairs.
// `queries` sorted, `places[k]` the best place of queries[k].
double sequence_reliability(const std::vector<int>& queries, std::vector<int> places) {
  int pairs = 0, follow = 0;
  for (std::size_t k = 1; k < queries.size(); ++k) {
    if (queries[k] != queries[k - 1] + 1) continue;
    ++pairs;
    follow += std::abs(places[k] - places[k - 1]) <= kFollowWindow;
  }
  if (pairs < kMinConsecutive) return std::numeric_limits<double>::quiet_NaN();
  std::sort(places.begin(), places.end());
  double close = 0;  // unordered pairs of queries whose best places are within the window
  for (std::size_t i = 0, j = 0; i < places.size(); ++i) {
    while (places[i] - places[j] > kFollowWindow) ++j;
    close += static_cast<double>(i - j);
  }
  const double n = static_cast<double>(places.size());
  const double chance = close / (n * (n - 1) / 2);
  if (chance >= 1) return 0.0;
  return (static_cast<double>(follow) / pairs - chance) / (1 - chance);
}

}  // namespace

void FusionStatistics::add_row(const Eigen::RowVectorXd& structure,
                               const Eigen::RowVectorXd& intensity, int query, int mask_width) {
  sum_s_ += structure.sum();
  sum_ss_ += structure.squaredNorm();
  sum_i_ += intensity.sum();
  sum_ii_ += intensity.squaredNorm();
  entries_ += static_cast<double>(structure.size());
  Eigen::RowVectorXd s = structure, g = intensity;
  row_zscore(s);
  row_zscore(g);
  const int bs = allowed_argmin(s, query, mask_width), bi = allowed_argmin(g, query, mask_width);
  if (bs < 0 || bi < 0) return;
  int allowed = 0;
  for (int j = 0; j < s.size(); ++j) allowed += std::abs(query - j) >= mask_width;
  const int k = std::max(1, static_cast<int>(std::lround(0.01 * allowed)));
  int better = 0;  // allowed places the structure half ranks above the intensity half's best
  for (int j = 0; j < s.size() && better < k; ++j) {
    if (std::abs(query - j) >= mask_width && s[j] < s[bi]) ++better;
  }
  agree_ += better < k;
  chance_sum_ += static_cast<double>(k) / allowed;
  peak_s_ -= s[bs];
  peak_i_ -= g[bi];
  ++counted_;
  bests_.push_back({query, bs, bi});
}

void FusionStatistics::merge(const FusionStatistics& o) {
  sum_s_ += o.sum_s_;
  sum_ss_ += o.sum_ss_;
  sum_i_ += o.sum_i_;
  sum_ii_ += o.sum_ii_;
  entries_ += o.entries_;
  peak_s_ += o.peak_s_;
  peak_i_ += o.peak_i_;
  chance_sum_ += o.chance_sum_;
  agree_ += o.agree_;
  counted_ += o.counted_;
  bests_.insert(bests_.end(), o.bests_.begin(), o.bests_.end());
}

FusionWeights FusionStatistics::weights(double structure_weight) const {
  FusionWeights w;
  w.structure = structure_weight;
  if (entries_ > 0) {
    w.structure_mean = sum_s_ / entries_;
    w.intensity_mean = sum_i_ / entries_;
    w.structure_std = deviation(sum_s_, sum_ss_, entries_);
    w.intensity_std = deviation(sum_i_, sum_ii_, entries_);
  }
  if (counted_ == 0) return w;
  w.structure_peak = peak_s_ / counted_;
  w.intensity_peak = peak_i_ / counted_;
  w.agreement = static_cast<double>(agree_) / counted_;
  w.chance = chance_sum_ / counted_;
  w.reliability =
      w.chance < 1 ? std::clamp((w.agreement - w.chance) / (1 - w.chance), 0.0, 1.0) : 1.0;
  std::vector<Best> by_query = bests_;
  std::sort(by_query.begin(), by_query.end(),
            [](const Best& a, const Best& b) { return a.query < b.query; });
  std::vector<int> queries, structure, intensity;
  for (const Best& b : by_query) {
    queries.push_back(b.query);
    structure.push_back(b.structure);
    intensity.push_back(b.intensity);
  }
  w.structure_sequence = sequence_reliability(queries, std::move(structure));
  w.intensity_sequence = sequence_reliability(queries, std::move(intensity));
  // The more peaked half leads unless its best matches follow the drive markedly less than the
  // other half's: then it is the one without signal.
  bool intensity_leads = w.intensity_peak > w.structure_peak;
  if (std::isfinite(w.structure_sequence) && std::isfinite(w.intensity_sequence)) {
    const double lead = intensity_leads ? w.intensity_sequence : w.structure_sequence;
    const double other = intensity_leads ? w.structure_sequence : w.intensity_sequence;
    if (lead < kSwitchShare * other) intensity_leads = !intensity_leads;
  }
  const double follower = w.reliability < kDropReliability ? 0.0 : w.reliability;
  if (intensity_leads) {
    w.structure *= follower;
  } else {
    w.intensity *= follower;
  }
  return w;
}

Eigen::RowVectorXd adaptive_fused_row(const Eigen::RowVectorXd& structure,
                                      const Eigen::RowVectorXd& intensity, const FusionWeights& w) {
  // One half alone ranks like that half (`--fusion structure` / `intensity`): fusing its z-scores
  // with nothing could only reorder queries against its own judgement.
  if (w.intensity == 0) return structure;
  if (w.structure == 0) return intensity;
  Eigen::RowVectorXd s = structure, g = intensity;
  row_zscore(s);
  row_zscore(g);
  const Eigen::RowVectorXd gs = (structure.array() - w.structure_mean) / w.structure_std;
  const Eigen::RowVectorXd gi = (intensity.array() - w.intensity_mean) / w.intensity_std;
  return 0.5 * (w.structure * (s + gs) + w.intensity * (g + gi));
}

}  // namespace loopscan
