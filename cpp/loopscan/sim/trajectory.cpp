#include "loopscan/sim/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <utility>

namespace loopscan::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;
// A step is a position fix correction, not motion, when it is this much longer than the steps
// around it (RobotCar's INS track has metre-sized sideways or backward jumps among 0.1-0.3 m
// steps) and longer than kMinJumpM.
constexpr double kJumpRatio = 3.0;
constexpr double kMinJumpM = 0.3;
constexpr int kJumpContext = 8;  // steps on each side for the typical step length

double median(std::vector<double> v) {
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// Horizontal (x, z) track with the correction jumps removed: the heading should follow the
// motion, and one jump would otherwise swing the heading of every frame within the window.
std::vector<Eigen::Vector2d> motion_track(const std::vector<Eigen::Vector3d>& p) {
  const int n = static_cast<int>(p.size());
  std::vector<Eigen::Vector2d> step(n, Eigen::Vector2d::Zero());
  for (int i = 1; i < n; ++i) step[i] = {p[i].x() - p[i - 1].x(), p[i].z() - p[i - 1].z()};
  std::vector<Eigen::Vector2d> q(n, Eigen::Vector2d::Zero());
  for (int i = 1; i < n; ++i) {
    std::vector<double> context;
    for (int k = std::max(1, i - kJumpContext); k <= std::min(n - 1, i + kJumpContext); ++k) {
      if (k != i) context.push_back(step[k].norm());
    }
    const double len = step[i].norm();
    const bool jump = len > kMinJumpM && (context.empty() || len > kJumpRatio * median(context));
    q[i] = q[i - 1] + (jump ? Eigen::Vector2d::Zero() : step[i]);
  }
  return q;
}

// Motion direction at frame i as the chord between the points half a window behind and ahead;
// one-sided near the ends; nothing when the track never leaves the window around i.
std::optional<double> windowed_yaw(const std::vector<Eigen::Vector2d>& q, std::size_t i,
                                   double half_window) {
  std::size_t ahead = i;
  while (ahead + 1 < q.size() && (q[ahead] - q[i]).norm() < half_window) ++ahead;
  std::size_t behind = i;
  while (behind > 0 && (q[behind] - q[i]).norm() < half_window) --behind;
  if ((q[ahead] - q[i]).norm() < half_window && (q[behind] - q[i]).norm() < half_window) {
    return std::nullopt;
  }
  const Eigen::Vector2d d = q[ahead] - q[behind];
  if (d.norm() < 1e-6) return std::nullopt;  // went out and came back
  return std::atan2(d.x(), d.y());
}

}  // namespace

std::vector<Eigen::Vector3d> Trajectory::centres() const {
  std::vector<Eigen::Vector3d> out;
  out.reserve(T_world_cam.size());
  for (const Eigen::Isometry3d& T : T_world_cam) out.push_back(T.translation());
  return out;
}

Eigen::Isometry3d level_pose(const Eigen::Vector3d& centre, double yaw_rad) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T.translation() = centre;
  return T;
}

double heading_yaw(const Eigen::Isometry3d& T_world_cam) {
  const Eigen::Vector3d forward = T_world_cam.linear().col(2);
  return std::atan2(forward.x(), forward.z());
}

double rotation_angle(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  // Via a quaternion: accurate for small angles (unlike acos of the trace) and tolerant of the
  // slightly non-orthonormal rotations found in GT files.
  const Eigen::Matrix3d R = a.linear().transpose() * b.linear();
  const Eigen::Quaterniond q = Eigen::Quaterniond(R).normalized();
  return 2.0 * std::atan2(q.vec().norm(), std::abs(q.w()));
}

Trajectory trajectory_from_kitti(const std::vector<Eigen::Matrix<double, 3, 4>>& poses,
                                 std::string name) {
  Trajectory t;
  t.name = std::move(name);
  t.T_world_cam.reserve(poses.size());
  for (const Eigen::Matrix<double, 3, 4>& P : poses) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.matrix().topRows<3>() = P;
    t.T_world_cam.push_back(T);
  }
  return t;
}

Trajectory trajectory_from_gps(const std::vector<Eigen::Vector3d>& northing_easting_down,
                               std::string name) {
  const std::vector<Eigen::Vector3d>& ned = northing_easting_down;
  std::vector<Eigen::Vector3d> p;
  p.reserve(ned.size());
  for (std::size_t i = 0; i < ned.size(); ++i) {
    if (!ned[i].allFinite()) {
      throw std::invalid_argument("trajectory_from_gps: non-finite GPS row " + std::to_string(i));
    }
    const Eigen::Vector3d d = ned[i] - ned.front();
    p.emplace_back(d.y(), d.z(), d.x());  // (east, down, north): right-handed, camera-like
  }

  const double half_window = 0.5 * gps_heading_window_m;
  const std::vector<Eigen::Vector2d> q = motion_track(p);
  std::vector<std::optional<double>> yaw(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const bool duplicate = i > 0 && (p[i] - p[i - 1]).norm() < 1e-3;
    yaw[i] = duplicate ? yaw[i - 1] : windowed_yaw(q, i, half_window);
    if (!yaw[i] && i > 0) yaw[i] = yaw[i - 1];
  }
  // Leading frames without a heading take the first available one (0 if the track never moves).
  double first = 0.0;
  for (const std::optional<double>& y : yaw) {
    if (y) {
      first = *y;
      break;
    }
  }

  Trajectory t;
  t.name = std::move(name);
  t.T_world_cam.reserve(p.size());
  for (std::size_t i = 0; i < p.size(); ++i)
    t.T_world_cam.push_back(level_pose(p[i], yaw[i].value_or(first)));
  return t;
}

std::vector<int> select_keyframes(const Trajectory& trajectory,
                                  const KeyframeSelection& selection) {
  std::vector<int> keyframes;
  if (trajectory.T_world_cam.empty()) return keyframes;
  const double min_rotation = selection.min_rotation_deg * kPi / 180.0;
  keyframes.push_back(0);
  for (std::size_t i = 1; i < trajectory.T_world_cam.size(); ++i) {
    const Eigen::Isometry3d& last = trajectory.T_world_cam[keyframes.back()];
    const Eigen::Isometry3d& current = trajectory.T_world_cam[i];
    const double moved = (current.translation() - last.translation()).norm();
    if (moved > selection.min_distance_m || rotation_angle(last, current) > min_rotation) {
      keyframes.push_back(static_cast<int>(i));
    }
  }
  return keyframes;
}

}  // namespace loopscan::sim
