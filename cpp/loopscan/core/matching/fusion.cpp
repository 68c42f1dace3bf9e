#include "loopscan/core/matching/fusion.hpp"

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

}  // namespace loopscan
