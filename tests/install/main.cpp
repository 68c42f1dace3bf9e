// Describes two rotated copies of a small cloud with the installed library; exits 0 when the
// Scan Context distance between them is near zero.
#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <loopscan/core/descriptors/describe.hpp>
#include <loopscan/core/matching/pair_distance.hpp>

int main() {
  loopscan::Cloud a;
  for (int i = 0; i < 400; ++i) {
    const double t = 0.05 * i;
    a.push_back({{10 * std::cos(t) + 0.1 * (i % 7), 1.5 + 0.2 * (i % 5), 12 * std::sin(1.3 * t)},
                 static_cast<float>(i % 256)});
  }
  loopscan::Cloud b = a;
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.8, Eigen::Vector3d::UnitY()).toRotationMatrix();
  for (auto& q : b) q.p = R * q.p;
  auto cfg = loopscan::DescriptorConfig::for_mode(loopscan::Mode::Default);
  cfg.scan_context.frame = loopscan::DescriptorFrame::Pca;  // rotation-invariant by construction
  cfg.scan_context.lateral_versions_m.clear();
  const auto sa = loopscan::describe(loopscan::Method::ScanContext, a, cfg);
  const auto sb = loopscan::describe(loopscan::Method::ScanContext, b, cfg);
  const double d = loopscan::scan_context_distance(sa, sb, loopscan::Component::Structure);
  std::printf("installed loopscan: %ld columns, distance %.3g\n", static_cast<long>(sa.cols()), d);
  return d < 1e-6 ? 0 : 1;
}
