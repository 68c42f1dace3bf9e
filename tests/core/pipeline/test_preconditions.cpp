// The core's preconditions: configs, poses, points and database values that used to run into
// undefined behaviour or unbounded work (a huge thread count, an infinite range, NaN
// payloads) are refused with std::invalid_argument, and points no scan could keep are dropped
// with the same result as if they had never been there.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "loopscan/core/database/database.hpp"
#include "loopscan/core/parallel.hpp"
#include "loopscan/core/pipeline/describe_sequence.hpp"
#include "loopscan/core/scan/camera_points.hpp"
#include "loopscan/core/scan/point_filter.hpp"
#include "loopscan/eval/place_evaluation.hpp"
#include "support/test_support.hpp"

namespace loopscan {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();

TEST(Preconditions, ImitationConfigsOutOfRangeAreRefused) {
  for (double range : {kInf, kNan, 1e308, 0.0, -5.0, 1001.0}) {
    ImitationConfig c;
    c.range_m = range;
    EXPECT_THROW(validate(c), std::invalid_argument) << range;
    EXPECT_THROW(ScanImitator{c}, std::invalid_argument) << range;
    EXPECT_THROW(cartesian_filter({}, range, 30, 60, Mode::Default), std::invalid_argument);
  }
  ImitationConfig many_cells;
  many_cells.voxel_divisions_xz = 1000;  // 2001^2 x 121 cells: a 4 GB table
  EXPECT_THROW(validate(many_cells), std::invalid_argument);
  ImitationConfig fine_polar;
  fine_polar.polar_resolution_deg = 0.0;
  EXPECT_THROW(validate(fine_polar), std::invalid_argument);
  EXPECT_NO_THROW(validate(ImitationConfig{}));
  ScanContextConfig sc;
  sc.max_radius_m = kInf;
  EXPECT_THROW(validate(sc), std::invalid_argument);
}

TEST(Preconditions, DescribeSequenceRefusesAbsurdThreadCountsAndNonFinitePoses) {
  std::vector<KeyframePose> poses(3);
  for (int i = 0; i < 3; ++i) poses[i].id = i;
  SequenceOptions o = SequenceOptions::make(Method::ScanContext, Mode::Default);
  for (int threads : {200000000, 0, -3}) {
    o.threads = threads;
    EXPECT_THROW(describe_sequence(poses, {}, o), std::invalid_argument) << threads;
  }
  o.threads = 2;
  // Out of id order (arrays not read from a file, e.g. from Python): refused, not misread.
  std::vector<KeyframePose> swapped = poses;
  std::swap(swapped[0], swapped[1]);
  EXPECT_THROW(describe_sequence(swapped, {}, o), std::invalid_argument);
  const std::vector<IdPoint> unsorted = {{2, {1, 0, 1}, 10.f}, {1, {1, 0, 1}, 10.f}};
  EXPECT_THROW(describe_sequence(poses, unsorted, o), std::invalid_argument);
  EXPECT_NO_THROW(describe_sequence(poses, {unsorted[1], unsorted[0]}, o));
  poses[1].T_cam_world(0, 3) = kNan;
  EXPECT_THROW(describe_sequence(poses, {}, o), std::invalid_argument);
}

TEST(Preconditions, UnusablePointsAreLeftOutAndCounted) {
  const Cloud street = test::street_cloud(3, 2000);
  std::vector<IdPoint> clean, dirty;
  for (const PointI& q : street) clean.push_back({0, q.p, q.intensity});
  dirty = clean;
  dirty.push_back({0, Eigen::Vector3d(kNan, 1, 2), 10.f});
  dirty.push_back({0, Eigen::Vector3d(1, 1e300, 2), 10.f});  // beyond single precision
  dirty.push_back({0, Eigen::Vector3d(1, 2, 3), std::numeric_limits<float>::infinity()});
  for (Mode mode : {Mode::Default, Mode::Reference}) {
    ImitationConfig c;
    c.mode = mode;
    c.init_frames = 0;
    ScanImitator a(c), b(c);
    Cloud sa, sb;
    ASSERT_TRUE(a.next_scan({}, clean.data(), clean.size(), false, ScanFilter::Polar, sa));
    ASSERT_TRUE(b.next_scan({}, dirty.data(), dirty.size(), false, ScanFilter::Polar, sb));
    EXPECT_EQ(b.unusable_points(), 3u);
    ASSERT_EQ(sa.size(), sb.size());
    for (std::size_t i = 0; i < sa.size(); ++i) EXPECT_EQ(sa[i].p, sb[i].p);
  }
}

// Points outside the range cube (Cartesian) or NaN (both filters) passed straight to the
// filters: dropped, and the rest filtered exactly as without them (the oracle).
TEST(Preconditions, FiltersDropPointsWithoutACellAndKeepTheRest) {
  const Cloud inside = test::street_cloud(5, 3000);
  Cloud with_outsiders = inside;
  for (int k = 0; k < 40; ++k) {  // spread through the cloud to reach the vector lanes
    const Eigen::Vector3d far = k % 3 == 0   ? Eigen::Vector3d(1e30, 0, 0)
                                : k % 3 == 1 ? Eigen::Vector3d(0, -46, 0)
                                             : Eigen::Vector3d(kNan, 1, 1);
    with_outsiders.insert(with_outsiders.begin() + 70 * k, PointI{far, 5.f});
  }
  for (ScanFilter f : {ScanFilter::Cartesian, ScanFilter::Polar}) {
    ImitationConfig c;
    const Cloud expected = filter_camera_points(to_camera_points(inside), f, c);
    Cloud in_range = with_outsiders;
    if (f == ScanFilter::Polar) {  // polar cells exist for any finite point: drop only NaN there
      in_range.erase(
          std::remove_if(in_range.begin(), in_range.end(),
                         [](const PointI& q) { return q.p.x() == 1e30 || q.p.y() == -46; }),
          in_range.end());
    }
    const Cloud got = filter_camera_points(to_camera_points(in_range), f, c);
    ASSERT_EQ(got.size(), expected.size()) << (f == ScanFilter::Polar ? "polar" : "cartesian");
    for (std::size_t i = 0; i < got.size(); ++i) EXPECT_EQ(got[i].p, expected[i].p);
  }
  Cloud nan_scan = inside;
  nan_scan[7].p.z() = kNan;
  EXPECT_THROW(describe(Method::M2dp, nan_scan, DescriptorConfig{}), std::invalid_argument);
}

TEST(Preconditions, TheDatabaseRefusesNonFiniteValuesAndNonsenseOptions) {
  DatabaseConfig bad_weight;
  bad_weight.structure_weight = -1e308;
  EXPECT_THROW(Database{bad_weight}, std::invalid_argument);
  DatabaseConfig cfg;
  cfg.method = Method::Delight;
  Database db(cfg);
  Signature s = Signature::Zero(rows_per_place(cfg.method), signature_columns(cfg.method));
  s(0, 5) = 3;
  db.add({0, 1}, {s});
  Signature nan = s;
  nan(3, 3) = kNan;
  EXPECT_THROW(db.add({0, 2}, {nan}), std::invalid_argument);
  EXPECT_THROW(db.query({nan}, 1), std::invalid_argument);
  PlaceDescriptor bad_frame{s};
  bad_frame.frame(0, 0) = kInf;
  EXPECT_THROW(db.add({0, 3}, bad_frame), std::invalid_argument);
  EXPECT_EQ(db.size(), 1u);  // nothing half-added
  QueryOptions o;
  o.uniqueness_ratio = kNan;
  EXPECT_THROW(db.query({s}, 1, o), std::invalid_argument);
  o = {};
  o.threads = 200000000;
  EXPECT_THROW(db.query({s}, 1, o), std::invalid_argument);
  EXPECT_THROW(db.query({s}, -1), std::invalid_argument);
  EXPECT_EQ(db.query({s}, 1).size(), 1u);
}

// A worker that throws (a bad signature, a caller's progress callback) reaches the caller as
// that exception after every thread joined, instead of ending the process.
TEST(Preconditions, ExceptionsOnWorkerThreadsReachTheCaller) {
  std::vector<int> done(4, 0);
  EXPECT_THROW(run_on_threads(4,
                              [&](int t) {
                                done[static_cast<std::size_t>(t)] = 1;
                                if (t == 2) throw std::invalid_argument("item of thread 2");
                              }),
               std::invalid_argument);
  EXPECT_EQ(done, (std::vector<int>{1, 1, 1, 1}));
  // Through the evaluation: a query of the wrong width, matched on two threads.
  const Signature good = Signature::Constant(1, 2400, 0.5), bad = Signature::Constant(1, 7, 0.5);
  const std::vector<Eigen::Vector3d> pos(3, Eigen::Vector3d::Zero());
  eval::PlaceEvaluationOptions o;
  o.threads = 2;
  EXPECT_THROW(eval::evaluate_places({good, bad, good}, {good, good, good}, pos, pos, o),
               std::invalid_argument);
}

}  // namespace
}  // namespace loopscan
