// Lane versions of a query: their candidates count only for places seen the other way round.
#include <gtest/gtest.h>

#include <random>

#include "loopscan/core/database/lane_query.hpp"
#include "support/random_signatures.hpp"

namespace loopscan {
namespace {

// Rows: up = -y, camera x, camera z (DescriptorFrame::Camera).
Eigen::Matrix3d camera_axes() {
  Eigen::Matrix3d m;
  m << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  return m;
}

// The signature seen turned by `shift` sectors (sector s moves to s + shift); mirrored: the
// sector order reversed (a mirror image, impossible in the camera frame).
Signature turned(const Signature& s, int shift, bool mirrored = false) {
  const int R = 20, S = 60;
  Signature out = s;
  for (int half = 0; half < 2; ++half) {
    for (int sec = 0; sec < S; ++sec) {
      const int to = mirrored ? (S - 1 - sec + shift) % S : (sec + shift) % S;
      for (int r = 0; r < R; ++r)
        out(0, half * R * S + to * R + r) = s(0, half * R * S + sec * R + r);
    }
  }
  return out;
}

bool contains(const std::vector<Candidate>& c, std::size_t index) {
  for (const Candidate& x : c) {
    if (x.index == index) return true;
  }
  return false;
}

TEST(LaneQuery, VersionsMatchOnlyPlacesSeenTheOtherWayRound) {
  std::mt19937 rng(11);
  Database db;
  std::vector<Signature> places;
  for (int i = 0; i < 40; ++i) {
    places.push_back(test::random_signature(Method::ScanContext, rng));
    db.add({0, i}, {places.back(), camera_axes()});
  }
  const Signature target = places[17];
  const PlaceDescriptor unrelated{test::random_signature(Method::ScanContext, rng), camera_axes()};
  QueryOptions exact;
  exact.retrieval = Retrieval::Exact;
  // Without versions: exactly the database's answer.
  const auto plain = query_with_lane_versions(db, unrelated, {}, 3, exact);
  const auto want = db.query(unrelated, 3, exact);
  ASSERT_EQ(plain.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) EXPECT_EQ(plain[i].index, want[i].index);
  // A version that sees place 17 turned by 180 degrees finds it, first.
  const auto reverse =
      query_with_lane_versions(db, unrelated, {{turned(target, 30), camera_axes()}}, 3, exact);
  ASSERT_FALSE(reverse.empty());
  EXPECT_EQ(reverse[0].index, 17u);
  EXPECT_NEAR(std::abs(reverse[0].yaw_rad), M_PI, 1e-9);
  // The same place seen the same way round, or mirrored, from a lane version: not a reverse drive.
  for (const Signature& v : {turned(target, 0), turned(target, 30, true), turned(target, 10)}) {
    const auto r = query_with_lane_versions(db, unrelated, {{v, camera_axes()}}, 3, exact);
    EXPECT_FALSE(contains(r, 17)) << "a lane version matched at the wrong yaw or mirrored";
    EXPECT_EQ(r.size(), 3u);
  }
  // One result per place, sorted by distance.
  const auto twice = query_with_lane_versions(db, {turned(target, 30), camera_axes()},
                                              {{turned(target, 30), camera_axes()}}, 5, exact);
  for (std::size_t i = 1; i < twice.size(); ++i) {
    EXPECT_LE(twice[i - 1].distance, twice[i].distance);
    EXPECT_NE(twice[i - 1].index, twice[i].index);
  }
}

}  // namespace
}  // namespace loopscan
