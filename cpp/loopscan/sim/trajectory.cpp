#include "loopscan/sim/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
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

namespace {

// A Dubins path (shortest drive with a bounded turning radius) of the form turn, straight, turn
// in the plane (X, Y) with headings theta along (cos, sin); turns: +1 counterclockwise.
struct TurnStraightTurn {
  Eigen::Vector2d c1, c2;  // turn centres
  int s1 = 1, s2 = 1;
  double theta0 = 0, straight_heading = 0, arc1 = 0, straight = 0, arc2 = 0, radius = 1;
  double length() const { return arc1 + straight + arc2; }

  static Eigen::Vector2d left(double theta) { return {-std::sin(theta), std::cos(theta)}; }
  // Pose at arc length `along` (clamped to the path).
  std::pair<Eigen::Vector2d, double> at(double along) const {
    if (along <= arc1) {
      const double theta = theta0 + s1 * along / radius;
      return {c1 - s1 * radius * left(theta), theta};
    }
    const Eigen::Vector2d t1 = c1 - s1 * radius * left(straight_heading);
    if (along <= arc1 + straight)
      return {t1 + (along - arc1) *
                       Eigen::Vector2d(std::cos(straight_heading), std::sin(straight_heading)),
              straight_heading};
    const double theta = straight_heading + s2 * std::min(along - arc1 - straight, arc2) / radius;
    return {c2 - s2 * radius * left(theta), theta};
  }
};

double positive_angle(double a) {
  const double m = std::fmod(a, 2 * kPi);
  return m < 0 ? m + 2 * kPi : m;
}

TurnStraightTurn shortest_turn_straight_turn(const Eigen::Vector2d& p0, double theta0,
                                             const Eigen::Vector2d& p1, double theta1,
                                             double radius) {
  TurnStraightTurn best;
  double best_length = std::numeric_limits<double>::infinity();
  for (int s1 : {1, -1})
    for (int s2 : {1, -1}) {
      TurnStraightTurn path;
      path.radius = radius;
      path.s1 = s1;
      path.s2 = s2;
      path.theta0 = theta0;
      path.c1 = p0 + s1 * radius * TurnStraightTurn::left(theta0);
      path.c2 = p1 + s2 * radius * TurnStraightTurn::left(theta1);
      const Eigen::Vector2d v = path.c2 - path.c1;
      const double d = v.norm(), alpha = std::atan2(v.y(), v.x());
      if (s1 == s2) {  // outer tangent, parallel to the centres' line
        path.straight = d;
        path.straight_heading = d > 0 ? alpha : theta0;
      } else {  // inner tangent: only between circles 2 radii apart
        if (d < 2 * radius) continue;
        path.straight = std::sqrt(d * d - 4 * radius * radius);
        path.straight_heading = alpha + std::atan2(2.0 * s1 * radius, path.straight);
      }
      path.arc1 = radius * positive_angle(s1 * (path.straight_heading - theta0));
      path.arc2 = radius * positive_angle(s2 * (theta1 - path.straight_heading));
      if (path.length() < best_length) {
        best_length = path.length();
        best = path;
      }
    }
  return best;
}

}  // namespace

std::vector<Eigen::Isometry3d> connector_back_to_start(const Trajectory& route) {
  const std::vector<Eigen::Isometry3d>& T = route.T_world_cam;
  if (T.size() < 2) throw std::invalid_argument("laps: a route needs at least two frames");
  std::vector<double> steps;
  for (std::size_t i = 1; i < T.size(); ++i)
    steps.push_back((T[i].translation() - T[i - 1].translation()).norm());
  const double step = median(steps);
  if (!(step > 0)) throw std::invalid_argument("laps: the route does not move");
  const Eigen::Vector3d from = T.back().translation(), to = T.front().translation();
  const double yaw_from = heading_yaw(T.back()), yaw_to = heading_yaw(T.front());
  const double turn = std::abs(std::remainder(yaw_to - yaw_from, 2 * kPi));
  if ((to - from).norm() < 1.5 * step && turn < 10.0 * kPi / 180.0) return {};  // a loop already
  // In (X, Y) = (z, x) a yaw is the heading angle theta of (cos, sin).
  const TurnStraightTurn path = shortest_turn_straight_turn(
      {from.z(), from.x()}, yaw_from, {to.z(), to.x()}, yaw_to, lap_connector_turn_radius_m);
  // Frames evenly spaced at about the route's step, strictly between its end and its start;
  // the height goes linearly from one to the other.
  const double length = path.length();
  const int frames = std::max(0, static_cast<int>(std::lround(length / step)) - 1);
  std::vector<Eigen::Isometry3d> out;
  for (int f = 1; f <= frames; ++f) {
    const double along = length * f / (frames + 1);
    const auto [q, theta] = path.at(along);
    const double y = from.y() + (to.y() - from.y()) * along / length;
    out.push_back(level_pose(Eigen::Vector3d(q.y(), y, q.x()), std::remainder(theta, 2 * kPi)));
  }
  return out;
}

std::vector<Eigen::Vector3d> lap_streets(const Trajectory& route, int laps) {
  std::vector<Eigen::Vector3d> streets = route.centres();
  if (laps > 1)
    for (const Eigen::Isometry3d& T : connector_back_to_start(route))
      streets.push_back(T.translation());
  return streets;
}

Trajectory drive_laps(const Trajectory& route, int laps) {
  if (laps < 1) throw std::invalid_argument("laps: at least 1");
  if (laps == 1) return route;
  const std::vector<Eigen::Isometry3d> connector = connector_back_to_start(route);
  Trajectory t;
  t.name = route.name + " x" + std::to_string(laps);
  for (int lap = 0; lap < laps; ++lap) {
    if (lap > 0) t.T_world_cam.insert(t.T_world_cam.end(), connector.begin(), connector.end());
    t.T_world_cam.insert(t.T_world_cam.end(), route.T_world_cam.begin(), route.T_world_cam.end());
  }
  return t;
}

}  // namespace loopscan::sim
