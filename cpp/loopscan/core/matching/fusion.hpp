#pragma once
// Fusing the structure and intensity difference rows (paper Eq. 1):
// D = w_s * rowz(D_structure) + rowz(D_intensity).
#include <string>
#include <vector>

#include <Eigen/Core>

namespace loopscan {

// Adaptive: Fused with the weights of adaptive_fusion_weights, per pair of place sets.
enum class Fusion { Fused, Structure, Intensity, Adaptive };

// "fused" | "structure" | "intensity"; throws std::invalid_argument otherwise.
Fusion parse_fusion(const std::string& name);
std::string fusion_name(Fusion fusion);

// In place: subtract the mean, divide by the standard deviation with the n - 1 normaliser
// (Matlab's normalize). A constant row becomes zeros.
void row_zscore(Eigen::Ref<Eigen::RowVectorXd> row);

// One difference row from the matcher's components (1 row for DELIGHT: returned as is).
// Adaptive combines like Fused with the given weights.
Eigen::RowVectorXd combine_components(const Eigen::MatrixXd& components, Fusion fusion,
                                      double structure_weight = 2.0, double intensity_weight = 1.0);

// Weights of the two halves for one pair of place sets, from the row z-scores of every query.
// How often the intensity half's best place is among the structure half's best k
// (k = 1 % of the places, at least 1) measures how far the halves agree beyond chance:
// r = (agreement - chance) / (1 - chance), clamped to [0, 1]. The half whose best matches
// stand out more (mean -min z) keeps its full weight (structure: w_s, intensity: 1), the other
// is scaled by r: halves that agree fuse like the paper, a half that contradicts the other
// (gray values across seasons) fades out. `excluded(q, j)`: columns a query may not match.
struct FusionWeights {
  double structure = 2.0, intensity = 1.0;
  double agreement = 0, chance = 0, reliability = 1;
  double structure_peak = 0, intensity_peak = 0;
};
FusionWeights adaptive_fusion_weights(const std::vector<Eigen::RowVectorXf>& structure_z,
                                      const std::vector<Eigen::RowVectorXf>& intensity_z,
                                      int mask_width, double structure_weight = 2.0);

}  // namespace loopscan
