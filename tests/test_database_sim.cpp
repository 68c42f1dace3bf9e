// The database on a simulated drive: relative yaw against ground truth at true revisits, and
// the online (streaming) query against the offline difference-matrix evaluation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "loopscan/core/database.hpp"
#include "loopscan/sim/simulated_places.hpp"

namespace loopscan {
namespace {

const sim::SimulatedPlaces& city_summer() {
  static const sim::SimulatedPlaces p = sim::simulate_places(
      sim::make_builtin_trajectory("city"), sim::Season::Summer, 7, 100, Method::ScanContext, 2);
  return p;
}

// Ground truth: the place keyframe's forward axis in the query camera frame, yaw about -y.
double gt_yaw(const Eigen::Isometry3d& query, const Eigen::Isometry3d& place) {
  const Eigen::Vector3d f = query.linear().transpose() * place.linear() * Eigen::Vector3d::UnitZ();
  return std::atan2(-f.x(), f.z());
}

TEST(DatabaseSim, YawAtTrueRevisitsMatchesGroundTruth) {
  const auto& s = city_summer();
  Database db;
  QueryOptions opt;
  opt.exclude_recent = 100;
  std::vector<double> errors_deg;
  for (std::size_t i = 0; i < s.places.size(); ++i) {
    const auto got = db.query(s.places[i], 1, opt);
    db.add({0, s.keyframe_ids[i]}, s.places[i]);
    if (got.empty()) continue;
    const std::size_t j = got[0].index;
    if ((s.T_world_cam[i].translation() - s.T_world_cam[j].translation()).norm() > 5.0) continue;
    const double e = std::remainder(got[0].yaw_rad - gt_yaw(s.T_world_cam[i], s.T_world_cam[j]),
                                    2 * M_PI);
    errors_deg.push_back(std::abs(e) * 180 / M_PI);
  }
  ASSERT_GE(errors_deg.size(), 50u);
  std::sort(errors_deg.begin(), errors_deg.end());
  const double median = errors_deg[errors_deg.size() / 2];
  const double p75 = errors_deg[errors_deg.size() * 3 / 4];
  std::printf("yaw error at %zu true revisits: median %.2f deg, p75 %.2f deg, max %.2f deg\n",
              errors_deg.size(), median, p75, errors_deg.back());
  // Most revisits are within half a sector; the tail is symmetric streets (180 deg) and
  // crossings seen from perpendicular directions, where the scans share little.
  EXPECT_LT(median, 3.0);
  EXPECT_LT(p75, 8.0);
}

}  // namespace
}  // namespace loopscan
