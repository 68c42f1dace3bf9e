#include "loopscan/core/matching/adaptive_fusion.hpp"

#include <algorithm>
#include <cmath>

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
  if (w.intensity_peak > w.structure_peak) {
    w.structure *= w.reliability;
  } else {
    w.intensity *= w.reliability;
  }
  return w;
}

Eigen::RowVectorXd adaptive_fused_row(const Eigen::RowVectorXd& structure,
                                      const Eigen::RowVectorXd& intensity, const FusionWeights& w) {
  Eigen::RowVectorXd s = structure, g = intensity;
  row_zscore(s);
  row_zscore(g);
  const Eigen::RowVectorXd gs = (structure.array() - w.structure_mean) / w.structure_std;
  const Eigen::RowVectorXd gi = (intensity.array() - w.intensity_mean) / w.intensity_std;
  return 0.5 * (w.structure * (s + gs) + w.intensity * (g + gi));
}

}  // namespace loopscan
