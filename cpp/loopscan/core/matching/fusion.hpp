#pragma once
// Fusing the structure and intensity difference rows (paper Eq. 1):
// D = w_s * rowz(D_structure) + rowz(D_intensity).
#include <string>

#include <Eigen/Core>

#include "loopscan/core/types.hpp"

namespace loopscan {

// Adaptive: see adaptive_fusion.hpp (weights and scales per pair of place sets).
enum class Fusion { Fused, Structure, Intensity, Adaptive };

// The fusion of an offline evaluation in each mode: the paper's per-row fusion in reference
// mode, adaptive fusion (adaptive_fusion.hpp) in default mode.
inline Fusion default_fusion(Mode mode) {
  return mode == Mode::Reference ? Fusion::Fused : Fusion::Adaptive;
}

// "fused" | "structure" | "intensity" | "adaptive"; throws std::invalid_argument otherwise.
Fusion parse_fusion(const std::string& name);
std::string fusion_name(Fusion fusion);

// In place: subtract the mean, divide by the standard deviation with the n - 1 normaliser
// (Matlab's normalize). A constant row becomes zeros.
void row_zscore(Eigen::Ref<Eigen::RowVectorXd> row);

// One difference row from the matcher's components (1 row for DELIGHT: returned as is).
// Adaptive combines like Fused with the given weights.
Eigen::RowVectorXd combine_components(const Eigen::MatrixXd& components, Fusion fusion,
                                      double structure_weight = 2.0, double intensity_weight = 1.0);

}  // namespace loopscan
