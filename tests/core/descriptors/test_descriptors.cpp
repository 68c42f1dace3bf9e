// Descriptor properties: PCA frame, Scan Context sector shifts, degenerate clouds, SVD sign.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "loopscan/core/descriptors/delight.hpp"
#include "loopscan/core/descriptors/describe.hpp"
#include "loopscan/core/descriptors/leading_singular.hpp"
#include "loopscan/core/descriptors/m2dp.hpp"
#include "loopscan/core/descriptors/pca_align.hpp"
#include "loopscan/core/descriptors/scan_context.hpp"
#include "loopscan/core/matching/pair_distance.hpp"
#include "support/test_support.hpp"

namespace loopscan {
namespace {

TEST(Pca, AxesOrderedByAscendingVarianceAndDecorrelated) {
  for (Mode mode : {Mode::Reference, Mode::Default}) {
    const Cloud aligned = pca_align(test::street_cloud(1), mode);
    Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const PointI& q : aligned) mean += q.p;
    EXPECT_LT((mean / aligned.size()).norm(), 1e-9);
    for (const PointI& q : aligned) cov += q.p * q.p.transpose();
    EXPECT_LT(std::abs(cov(0, 1)) + std::abs(cov(0, 2)) + std::abs(cov(1, 2)), 1e-6 * cov.trace());
    EXPECT_LE(cov(0, 0), cov(1, 1));
    EXPECT_LE(cov(1, 1), cov(2, 2));
  }
}

TEST(ScanContext, RotationAboutUpAxisShiftsSectors) {
  ScanContextConfig cfg;
  cfg.mode = Mode::Default;
  // Points at sector centres so that no rounding can move them across a boundary.
  std::mt19937 rng(5);
  Cloud aligned;
  for (int i = 0; i < 500; ++i) {
    const int sector = rng() % 60, ring = rng() % 20;
    const double angle = -M_PI + (sector + 0.5) * 2 * M_PI / 60;
    const double radius = (ring + 0.5) * 45.0 / 20;
    aligned.push_back(
        {{double(rng() % 100) / 10.0, radius * std::cos(angle), radius * std::sin(angle)},
         float(rng() % 256)});
  }
  const ScanContext base = scan_context_of_aligned(aligned, cfg);
  for (int k : {1, 7, 30, 59}) {
    const double a = k * 2 * M_PI / 60;
    Cloud rotated = aligned;
    for (PointI& q : rotated) {
      const double y = q.p(1), z = q.p(2);
      q.p(1) = std::cos(a) * y - std::sin(a) * z;
      q.p(2) = std::sin(a) * y + std::cos(a) * z;
    }
    const ScanContext sc = scan_context_of_aligned(rotated, cfg);
    for (int s = 0; s < 60; ++s) {
      for (int r = 0; r < 20; ++r) {
        ASSERT_DOUBLE_EQ(sc.structure(((s + k) % 60) * 20 + r), base.structure(s * 20 + r));
        ASSERT_EQ(sc.intensity(((s + k) % 60) * 20 + r), base.intensity(s * 20 + r));
      }
    }
  }
}

TEST(ScanContext, LateralVersionsAreTheDescriptorCentredAside) {
  const Cloud c = test::street_cloud(4, 3000);
  DescriptorConfig cfg = DescriptorConfig::for_mode(Mode::Default);
  ASSERT_EQ(cfg.scan_context.frame, DescriptorFrame::Camera);
  const std::vector<double> versions = cfg.scan_context.lateral_versions_m;
  ASSERT_FALSE(versions.empty());
  const Signature all = describe(Method::ScanContext, c, cfg);
  ASSERT_EQ(all.rows(), 1 + static_cast<Eigen::Index>(versions.size()));
  cfg.scan_context.lateral_versions_m.clear();
  EXPECT_EQ(describe(Method::ScanContext, c, cfg), all.topRows(1));
  for (std::size_t v = 0; v < versions.size(); ++v) {
    cfg.scan_context.lateral_offset_m = versions[v];
    EXPECT_EQ(describe(Method::ScanContext, c, cfg), all.row(v + 1)) << versions[v] << " m";
  }
  // The same scene seen from a camera one lane (3.5 m) to the left: its version centred 3.5 m
  // right of it is the place, so the query with versions matches (nearly) exactly, the centred
  // descriptor alone does not.
  Cloud aside = c;
  for (PointI& q : aside) q.p.x() += 3.5;  // camera x points right
  DescriptorConfig with = DescriptorConfig::for_mode(Mode::Default), without = with;
  without.scan_context.lateral_versions_m.clear();
  const Signature place = describe(Method::ScanContext, c, without);
  const double d_with = scan_context_distance(describe(Method::ScanContext, aside, with), place,
                                              Component::Structure);
  const double d_without = scan_context_distance(describe(Method::ScanContext, aside, without),
                                                 place, Component::Structure);
  EXPECT_LT(d_with, 1e-9);
  EXPECT_GT(d_without, d_with + 0.01);
  // In the centroid frame the versions move the (street-centred) descriptor aside too.
  with.scan_context.frame = DescriptorFrame::Centroid;
  const Signature centred = describe(Method::ScanContext, c, with);
  for (Eigen::Index v = 1; v < centred.rows(); ++v) EXPECT_NE(centred.row(v), centred.row(0)) << v;
}

TEST(ScanContext, ReferenceLeaksBeyondLastRingDefaultDrops) {
  ScanContextConfig cfg;
  // One point just beyond the max radius in the first sector (angle -pi + small).
  const double a = -M_PI + 0.01;
  const Cloud aligned{{{0.0, 46 * std::cos(a), 46 * std::sin(a)}, 200.f},
                      {{2.0, 46 * std::cos(a), 46 * std::sin(a)}, 200.f}};
  cfg.mode = Mode::Reference;
  EXPECT_GT(scan_context_of_aligned(aligned, cfg).structure.sum(), 0.0);  // ring 20 -> next sector
  cfg.mode = Mode::Default;
  EXPECT_EQ(scan_context_of_aligned(aligned, cfg).structure.sum(), 0.0);
}

TEST(Descriptors, EmptyTinyAndDegenerateCloudsAreFinite) {
  const std::vector<Cloud> clouds = {
      {},
      {{{1, 2, 3}, 10.f}},
      {{{1, 2, 3}, 10.f}, {{1, 2, 3}, 20.f}},                                         // duplicates
      {{{0, 0, 1}, 10.f}, {{0, 0, 2}, 20.f}, {{0, 0, 3}, 30.f}},                      // collinear
      {{{0, 0, 1}, 255.f}, {{1, 0, 1}, 0.f}, {{0, 1, 1}, 128.f}, {{1, 1, 1}, 3.f}}};  // planar
  for (const Cloud& c : clouds) {
    for (Method m : {Method::ScanContext, Method::M2dp, Method::Delight}) {
      const DescriptorConfig cfg = DescriptorConfig::for_mode(Mode::Default);
      const Signature s = describe(m, c, cfg);
      // Scan Context: the place and its lateral versions.
      const auto versions = static_cast<Eigen::Index>(cfg.scan_context.lateral_versions_m.size());
      EXPECT_EQ(s.rows(), rows_per_place(m) + (m == Method::ScanContext ? versions : 0));
      EXPECT_EQ(s.cols(), signature_columns(m));
      EXPECT_TRUE(s.allFinite()) << method_name(m) << " on " << c.size() << " points";
    }
  }
}

TEST(Delight, RegionsAndCountsAddUp) {
  const Cloud c = test::street_cloud(2, 1000);
  const Signature h = delight_signature(c, DelightConfig{});
  EXPECT_DOUBLE_EQ(h.sum(), 1000.0);
  DelightConfig cfg;
  EXPECT_EQ(delight_region({1, 1, 1}, cfg), 7);
  EXPECT_EQ(delight_region({-1, -1, -1}, cfg), 0);
  EXPECT_EQ(delight_region({20, -1, -1}, cfg), 9);
}

TEST(M2dp, CountsAddUpAndSingularPairMatchesJacobi) {
  M2dpConfig cfg;
  const Cloud aligned = pca_align(test::street_cloud(3, 2000), Mode::Default);
  const M2dpMatrices m = m2dp_matrices(aligned, cfg);
  // Default mode keeps log(1 + count): back to counts, every point within the max radius lands
  // in exactly one bin of every plane.
  const Eigen::MatrixXd counts = m.count.array().exp() - 1.0;
  EXPECT_LT((counts.array() - counts.array().round()).abs().maxCoeff(), 1e-9);
  for (Eigen::Index k = 0; k < counts.rows(); ++k) EXPECT_LE(counts.row(k).sum(), 2000.0 + 1e-6);
  EXPECT_GT(counts.sum(), 0.9 * 2000 * 64);
  for (const Eigen::MatrixXd* a : {&m.count, &m.gray}) {
    const SingularPair fast = leading_singular_pair(*a, Mode::Default);
    const SingularPair exact = leading_singular_pair(*a, Mode::Reference);
    const double sign = fast.u.dot(exact.u) < 0 ? -1.0 : 1.0;
    EXPECT_LT((fast.u - sign * exact.u).norm(), 1e-9);
    EXPECT_LT((fast.v - sign * exact.v).norm(), 1e-9);
    EXPECT_GT(fast.u.sum(), 0.0);  // canonical sign
  }
}

TEST(M2dp, VersionsCoverThePcaSignAmbiguity) {
  // Default mode: right-handed PCA basis, so one of the 16 version pairs matches a moved copy.
  const Cloud c = test::street_cloud(4, 2000);
  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.1, 1, 0.2).normalized()).toRotationMatrix();
  const Signature a = m2dp_signature(c, M2dpConfig{});
  const Signature b = m2dp_signature(test::transformed(c, R, {3, -1, 7}), M2dpConfig{});
  double best = 0;
  for (int i = 0; i < 4; ++i) {
    for (int j = 0; j < 4; ++j) best = std::max(best, a.row(i).head(192).dot(b.row(j).head(192)));
  }
  EXPECT_GT(best, 1.0 - 1e-6);
}

}  // namespace
}  // namespace loopscan
