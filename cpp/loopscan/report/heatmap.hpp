#pragma once
// A matrix as an SVG image (e.g. a Scan Context: rings x sectors), gray scale, with a title and
// axis labels.
#include <string>

#include <Eigen/Core>

namespace loopscan::report {

std::string heatmap_svg(const Eigen::MatrixXd& values, const std::string& title,
                        const std::string& x_label, const std::string& y_label, int cell_px = 10);

}  // namespace loopscan::report
