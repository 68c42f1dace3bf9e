#pragma once
// Fusing the structure and intensity difference rows (paper Eq. 1):
// D = w_s * rowz(D_structure) + rowz(D_intensity).
#include <string>

#include <Eigen/Core>

namespace loopscan {

enum class Fusion { Fused, Structure, Intensity };

// "fused" | "structure" | "intensity"; throws std::invalid_argument otherwise.
Fusion parse_fusion(const std::string& name);
std::string fusion_name(Fusion fusion);

// In place: subtract the mean, divide by the standard deviation with the n - 1 normaliser
// (Matlab's normalize). A constant row becomes zeros.
void row_zscore(Eigen::Ref<Eigen::RowVectorXd> row);

// One difference row from the matcher's components (1 row for DELIGHT: returned as is).
Eigen::RowVectorXd combine_components(const Eigen::MatrixXd& components, Fusion fusion,
                                      double structure_weight = 2.0);

}  // namespace loopscan
