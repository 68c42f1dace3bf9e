// Distances: invariance to rigid motion, symmetry, fast matchers against the pair oracles,
// fusion.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "loopscan/core/descriptors/describe.hpp"
#include "loopscan/core/matching/fusion.hpp"
#include "loopscan/core/matching/pair_distance.hpp"
#include "loopscan/core/matching/place_matcher.hpp"
#include "support/test_support.hpp"

namespace loopscan {
namespace {

double distance(Method m, const Signature& a, const Signature& b, Component c) {
  if (m == Method::ScanContext) return scan_context_distance(a, b, c);
  if (m == Method::M2dp) return m2dp_distance(a, b, c);
  return delight_distance(a, b);
}

constexpr Method kMethods[] = {Method::ScanContext, Method::M2dp, Method::Delight};

TEST(Distances, RigidMotionLeavesDistancesNearZero) {
  const Cloud c = test::street_cloud(11);
  DescriptorConfig cfg = DescriptorConfig::for_mode(Mode::Default);
  cfg.scan_context.frame = DescriptorFrame::Pca;  // the PCA frame is what makes it invariant
  cfg.scan_context.lateral_versions_m.clear();
  for (double angle : {0.3, 1.9, -2.8}) {
    const Eigen::Matrix3d R =
        Eigen::AngleAxisd(angle, Eigen::Vector3d(0.2, 1.0, -0.1).normalized()).toRotationMatrix();
    const Cloud moved = test::transformed(c, R, {4.0, -0.5, 12.0});
    for (Method m : kMethods) {
      const Signature a = describe(m, c, cfg), b = describe(m, moved, cfg);
      for (Component part : {Component::Structure, Component::Intensity}) {
        // M2DP's [u; v] rows have norm sqrt(2), so its self distance is -0.5, not 0.
        EXPECT_NEAR(distance(m, a, b, part), distance(m, a, a, part), 1e-6)
            << method_name(m) << " angle " << angle;
      }
      EXPECT_GT(distance(m, a, describe(m, test::street_cloud(99), cfg), Component::Structure),
                distance(m, a, a, Component::Structure) + 1e-5)
          << "a different place must not be at distance 0";
    }
  }
}

TEST(Distances, SymmetricAndZeroOnSelf) {
  const DescriptorConfig cfg = DescriptorConfig::for_mode(Mode::Default);
  for (Method m : kMethods) {
    const Signature a = describe(m, test::street_cloud(1), cfg);
    const Signature b = describe(m, test::street_cloud(2), cfg);
    for (Component part : {Component::Structure, Component::Intensity}) {
      EXPECT_NEAR(distance(m, a, b, part), distance(m, b, a, part), 1e-12) << method_name(m);
      EXPECT_NEAR(distance(m, a, a, part), m == Method::M2dp ? -0.5 : 0.0, 1e-12) << method_name(m);
    }
  }
}

TEST(Distances, EmptySignaturesAreFinite) {
  const DescriptorConfig cfg = DescriptorConfig::for_mode(Mode::Default);
  for (Method m : kMethods) {
    const Signature e = describe(m, {}, cfg), a = describe(m, test::street_cloud(1), cfg);
    EXPECT_TRUE(std::isfinite(distance(m, e, a, Component::Structure)));
    EXPECT_TRUE(std::isfinite(distance(m, e, e, Component::Intensity)));
  }
}

// nanoflann-style: the fast path against the oracle on many sizes with fixed seeds.
TEST(Matchers, AgreeWithPairOraclesAcrossSizes) {
  for (Method m : kMethods) {
    for (Precision precision : {Precision::Float, Precision::Double}) {
      const double tol = precision == Precision::Float ? 2e-5 : 1e-11;
      for (int n : {1, 3, 8, 17}) {
        std::vector<Signature> db;
        for (int i = 0; i < n; ++i) {
          db.push_back(
              describe(m, test::street_cloud(100 + i, 1500),
                       DescriptorConfig::for_mode(i % 2 ? Mode::Reference : Mode::Default)));
        }
        const auto matcher = make_matcher(m, precision);
        for (const Signature& s : db) matcher->add(s);
        ASSERT_EQ(matcher->size(), static_cast<std::size_t>(n));
        Eigen::MatrixXd rows;
        const Signature& q = db[n / 2];
        matcher->distances(q, rows);
        ASSERT_EQ(rows.cols(), n);
        for (int j = 0; j < n; ++j) {
          for (int c = 0; c < matcher->components(); ++c) {
            const double oracle = distance(m, q, db[j], Component(c));
            EXPECT_NEAR(rows(c, j), oracle, tol * std::max(1.0, std::abs(oracle)))
                << method_name(m) << " n=" << n << " j=" << j << " c=" << c;
          }
        }
      }
    }
  }
}

TEST(Fusion, RowZscoreAndWeights) {
  Eigen::RowVectorXd r(4);
  r << 1, 2, 3, 4;
  row_zscore(r);
  EXPECT_NEAR(r.mean(), 0.0, 1e-15);
  EXPECT_NEAR(r.squaredNorm() / 3.0, 1.0, 1e-12);  // n - 1 normaliser
  Eigen::RowVectorXd flat = Eigen::RowVectorXd::Constant(5, 2.0);
  row_zscore(flat);
  EXPECT_EQ(flat, Eigen::RowVectorXd::Zero(5));
  Eigen::MatrixXd comps(2, 3);
  comps << 0, 1, 2, 5, 5, 8;
  Eigen::RowVectorXd s = comps.row(0), i = comps.row(1);
  row_zscore(s);
  row_zscore(i);
  EXPECT_TRUE(combine_components(comps, Fusion::Fused, 2.0).isApprox(2 * s + i));
  EXPECT_EQ(combine_components(comps, Fusion::Structure), comps.row(0));
  EXPECT_EQ(combine_components(comps, Fusion::Intensity), comps.row(1));
  EXPECT_THROW(parse_fusion("both"), std::invalid_argument);
}

}  // namespace
}  // namespace loopscan
