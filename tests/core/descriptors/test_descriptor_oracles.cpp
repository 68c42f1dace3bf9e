// Fast descriptor paths against straightforward re-implementations (std::atan2, std::sqrt,
// one centre at a time), bit for bit, on random clouds and on points placed on bin boundaries.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "loopscan/core/descriptors/describe.hpp"
#include "loopscan/core/descriptors/pca_align.hpp"
#include "loopscan/core/descriptors/scan_context.hpp"
#include "support/test_support.hpp"

namespace loopscan {
namespace {

// Default-mode Scan Context of one centre, written from the definition.
Eigen::RowVectorXd scan_context_oracle(const Cloud& aligned, const ScanContextConfig& c, double cx,
                                       double cy) {
  const int R = c.rings, S = c.sectors, B = R * S;
  double mean = 0;
  for (const PointI& q : aligned) mean += q.intensity;
  if (!aligned.empty()) mean /= static_cast<double>(aligned.size());
  std::vector<double> low(B), high(B), gray(B), count(B);
  for (const PointI& q : aligned) {
    const double a1 = q.p(1) - cx, a2 = q.p(2) - cy;
    const int ring =
        static_cast<int>(std::floor(std::sqrt(a1 * a1 + a2 * a2) * (R / c.max_radius_m)));
    if (ring >= R) continue;
    const int sector =
        static_cast<int>(std::floor((std::atan2(a2, a1) + M_PI) * (S / (2.0 * M_PI)))) % S;
    const int b = sector * R + ring;
    const double h = q.p(0);
    low[b] = count[b] == 0 ? h : std::min(low[b], h);
    high[b] = count[b] == 0 ? h : std::max(high[b], h);
    gray[b] += q.intensity;
    count[b] += 1;
  }
  Eigen::RowVectorXd row(2 * B);
  for (int b = 0; b < B; ++b) {
    const bool any = count[b] > 0;
    row(b) =
        c.max_height ? (any ? std::max(0.0, high[b] + c.sensor_height_m) : 0.0) : high[b] - low[b];
    row(B + b) = any && gray[b] / count[b] > mean ? 1.0 : 0.0;
  }
  return row;
}

// Random points plus points on sector rays, ring circles, the axes and the centres themselves.
Cloud boundary_cloud(unsigned seed, const ScanContextConfig& c) {
  Cloud cloud = test::street_cloud(seed, 1500);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-50.0, 50.0);
  auto add = [&](double x, double z) {  // camera frame: x right, y down, z forward
    cloud.push_back({{x, u(rng) / 10, z}, static_cast<float>(rng() % 256)});
  };
  for (int i = 0; i < 300; ++i) add(u(rng), u(rng));
  for (double off : {0.0, -3.5, -1.75, 1.75, 3.5}) {
    add(off, 0.0);  // a version's centre
    for (int s = 0; s < 2 * c.sectors; ++s) {
      const double a = s * M_PI / c.sectors, r = std::abs(u(rng)) * 0.9;
      add(off + r * std::cos(a), r * std::sin(a));  // on (or halfway between) sector rays
    }
    for (int k = 0; k <= c.rings; ++k) {
      const double r = k * c.max_radius_m / c.rings;
      add(off + r, 0.0);
      add(off, -r);
      add(off - r * std::sqrt(0.5), r * std::sqrt(0.5));
    }
  }
  return cloud;
}

TEST(ScanContextOracle, OnePassVersionsEqualTheDefinition) {
  std::vector<ScanContextConfig> configs;
  for (int sectors : {60, 40, 120}) {
    for (int rings : {20, 7}) {
      ScanContextConfig c = DescriptorConfig::for_mode(Mode::Default).scan_context;
      c.sectors = sectors;
      c.rings = rings;
      configs.push_back(c);
    }
  }
  configs.push_back(configs.front());
  configs.back().max_height = true;
  configs.push_back(configs.front());
  configs.back().frame = DescriptorFrame::Centroid;
  int compared = 0;
  for (const ScanContextConfig& c : configs) {
    for (unsigned seed : {1u, 2u, 3u}) {
      const Cloud scan = boundary_cloud(seed, c);
      Eigen::Matrix3d axes;
      const Cloud aligned = align_scan(scan, c.frame, c.mode, &axes, c.lateral_offset_m);
      const Signature fast = scan_context_signature(scan, c);
      ASSERT_EQ(fast.rows(), 1 + static_cast<Eigen::Index>(c.lateral_versions_m.size()));
      for (Eigen::Index v = 0; v < fast.rows(); ++v) {
        const double off = v > 0 ? c.lateral_versions_m[v - 1] : 0.0;
        const Eigen::Vector3d side = axes * Eigen::Vector3d(off, 0, 0);
        const Eigen::RowVectorXd want = scan_context_oracle(aligned, c, side(1), side(2));
        ASSERT_EQ(fast.row(v), want)
            << c.sectors << " x " << c.rings << " seed " << seed << " version " << v;
        ++compared;
      }
    }
  }
  EXPECT_EQ(compared, 8 * 3 * 5);
}

TEST(ScanContextOracle, EmptyAndSinglePointScans) {
  const ScanContextConfig c = DescriptorConfig::for_mode(Mode::Default).scan_context;
  EXPECT_EQ(scan_context_signature({}, c).sum(), 0.0);
  const Cloud one{{{0.0, 0.0, 0.0}, 7.f}};  // at the place's own centre: ring 0
  const Signature s = scan_context_signature(one, c);
  EXPECT_EQ(s.row(0), scan_context_oracle(align_scan(one, c.frame, c.mode), c, 0.0, 0.0));
  for (int n = 1; n <= 19; ++n) {  // every tail length of the 2-, 4- and 8-lane kernels
    const Cloud small = test::street_cloud(n, n);
    const Cloud aligned = align_scan(small, c.frame, c.mode);
    EXPECT_EQ(scan_context_signature(small, c).row(0), scan_context_oracle(aligned, c, 0.0, 0.0))
        << n;
  }
}

}  // namespace
}  // namespace loopscan
