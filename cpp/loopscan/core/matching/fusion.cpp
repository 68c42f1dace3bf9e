#include "loopscan/core/matching/fusion.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace loopscan {

Fusion parse_fusion(const std::string& name) {
  if (name == "fused") return Fusion::Fused;
  if (name == "structure") return Fusion::Structure;
  if (name == "intensity") return Fusion::Intensity;
  if (name == "adaptive") return Fusion::Adaptive;
  throw std::invalid_argument("unknown fusion '" + name +
                              "' (expected adaptive, fused, structure or intensity)");
}

std::string fusion_name(Fusion fusion) {
  switch (fusion) {
    case Fusion::Fused:
      return "fused";
    case Fusion::Structure:
      return "structure";
    case Fusion::Intensity:
      return "intensity";
    case Fusion::Adaptive:
      return "adaptive";
  }
  return "?";
}

void row_zscore(Eigen::Ref<Eigen::RowVectorXd> row) {
  const Eigen::Index n = row.size();
  if (n == 0) return;
  const double mean = row.mean();
  row.array() -= mean;
  const double var = n > 1 ? row.squaredNorm() / static_cast<double>(n - 1) : 0.0;
  if (var > 0) {
    row /= std::sqrt(var);
  } else {
    row.setZero();
  }
}

Eigen::RowVectorXd combine_components(const Eigen::MatrixXd& components, Fusion fusion,
                                      double structure_weight, double intensity_weight) {
  if (components.rows() == 1) return components.row(0);
  if (fusion == Fusion::Structure) return components.row(0);
  if (fusion == Fusion::Intensity) return components.row(1);
  Eigen::RowVectorXd s = components.row(0), i = components.row(1);
  row_zscore(s);
  row_zscore(i);
  return structure_weight * s + intensity_weight * i;
}

namespace {

// Index of the smallest allowed entry of a row (-1 when every column is excluded).
int allowed_argmin(const Eigen::RowVectorXf& row, int query, int mask_width) {
  int best = -1;
  for (int j = 0; j < row.size(); ++j) {
    if (std::abs(query - j) < mask_width) continue;
    if (best < 0 || row[j] < row[best]) best = j;
  }
  return best;
}

}  // namespace

FusionWeights adaptive_fusion_weights(const std::vector<Eigen::RowVectorXf>& structure_z,
                                      const std::vector<Eigen::RowVectorXf>& intensity_z,
                                      int mask_width, double structure_weight) {
  FusionWeights w;
  w.structure = structure_weight;
  const int n = static_cast<int>(std::min(structure_z.size(), intensity_z.size()));
  if (n == 0) return w;
  const int m = static_cast<int>(structure_z[0].size());
  const int k = std::max(1, static_cast<int>(std::lround(0.01 * m)));
  int agree = 0, counted = 0;
  for (int q = 0; q < n; ++q) {
    const Eigen::RowVectorXf& s = structure_z[q];
    const int bi = allowed_argmin(intensity_z[q], q, mask_width);
    const int bs = allowed_argmin(s, q, mask_width);
    if (bi < 0 || bs < 0) continue;
    ++counted;
    w.structure_peak -= s[bs];
    w.intensity_peak -= intensity_z[q][bi];
    // Rank of the intensity half's best place in the structure row (allowed columns only).
    int better = 0;
    for (int j = 0; j < m && better < k; ++j) {
      if (std::abs(q - j) >= mask_width && s[j] < s[bi]) ++better;
    }
    agree += better < k;
  }
  if (counted == 0) return w;
  w.structure_peak /= counted;
  w.intensity_peak /= counted;
  w.agreement = static_cast<double>(agree) / counted;
  w.chance = std::min(1.0, static_cast<double>(k) / m);
  w.reliability =
      w.chance < 1 ? std::clamp((w.agreement - w.chance) / (1 - w.chance), 0.0, 1.0) : 1.0;
  if (w.intensity_peak > w.structure_peak) {
    w.structure *= w.reliability;
  } else {
    w.intensity *= w.reliability;
  }
  return w;
}

}  // namespace loopscan
