// Built-in routes: a polyline through street-grid intersections, shifted into the right-hand
// lane and smoothed with circular arcs at the turns, then sampled at a fixed step per frame.
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "loopscan/sim/trajectory.hpp"

namespace loopscan::sim {
namespace {

constexpr double kPi = 3.14159265358979323846;

struct RouteStyle {
  double lane_offset_m = 1.75;   // right-hand traffic: drive right of the street axis
  double right_radius_m = 10.0;  // tight right turns ...
  double left_radius_m = 16.0;   // ... wider left turns across the junction
  double step_m = 1.0;           // arc length per frame
};

// Unit direction of yaw (yaw 0 = +z, yaw pi/2 = +x), as (x, z).
Eigen::Vector2d direction(double yaw) { return {std::sin(yaw), std::cos(yaw)}; }
double yaw_of(const Eigen::Vector2d& d) { return std::atan2(d.x(), d.y()); }
double wrap(double a) { return std::atan2(std::sin(a), std::cos(a)); }

// A straight line (curvature 0) or a circular arc; positive curvature turns right (yaw grows).
struct Piece {
  Eigen::Vector2d start;
  double yaw0 = 0.0;
  double length = 0.0;
  double curvature = 0.0;

  void at(double s, Eigen::Vector2d& p, double& yaw) const {
    yaw = yaw0 + curvature * s;
    if (curvature == 0.0) {
      p = start + s * direction(yaw0);
      return;
    }
    // Closed form of the integral of direction(yaw0 + k s) ds.
    p = start +
        Eigen::Vector2d(std::cos(yaw0) - std::cos(yaw), std::sin(yaw) - std::sin(yaw0)) / curvature;
  }
};

std::vector<Piece> build_pieces(const std::vector<Eigen::Vector2d>& waypoints,
                                const RouteStyle& style) {
  const std::size_t n = waypoints.size();
  std::vector<Eigen::Vector2d> d(n - 1), right(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    d[i] = (waypoints[i + 1] - waypoints[i]).normalized();
    right[i] = {d[i].y(), -d[i].x()};
  }
  // Lane corners: where the offset lines of two consecutive segments meet (miter point).
  std::vector<Eigen::Vector2d> corner(n);
  corner[0] = waypoints[0] + style.lane_offset_m * right[0];
  corner[n - 1] = waypoints[n - 1] + style.lane_offset_m * right[n - 2];
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const double c = right[i - 1].dot(right[i]);
    if (c < -0.5) throw std::logic_error("built-in route: U-turns are not supported");
    corner[i] = waypoints[i] + style.lane_offset_m * (right[i - 1] + right[i]) / (1.0 + c);
  }

  std::vector<Piece> pieces;
  Eigen::Vector2d from = corner[0];
  auto add_line = [&](const Eigen::Vector2d& to, const Eigen::Vector2d& dir) {
    const double len = (to - from).dot(dir);
    if (len < 0.0) throw std::logic_error("built-in route: street too short for its turns");
    pieces.push_back({from, yaw_of(dir), len, 0.0});
  };
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const double turn = wrap(yaw_of(d[i]) - yaw_of(d[i - 1]));
    if (std::abs(turn) < 1e-9) continue;  // straight through the junction
    const double r = turn > 0 ? style.right_radius_m : style.left_radius_m;
    const double tangent = r * std::tan(std::abs(turn) / 2.0);
    add_line(corner[i] - tangent * d[i - 1], d[i - 1]);
    const Eigen::Vector2d arc_start = corner[i] - tangent * d[i - 1];
    pieces.push_back(
        {arc_start, yaw_of(d[i - 1]), r * std::abs(turn), (turn > 0 ? 1.0 : -1.0) / r});
    from = corner[i] + tangent * d[i];
  }
  add_line(corner[n - 1], d[n - 2]);
  return pieces;
}

Trajectory sample_route(const std::string& name, const std::vector<Eigen::Vector2d>& waypoints,
                        const RouteStyle& style = {}) {
  const std::vector<Piece> pieces = build_pieces(waypoints, style);
  double total = 0.0;
  for (const Piece& piece : pieces) total += piece.length;

  Trajectory t;
  t.name = name;
  std::size_t k = 0;
  double piece_start = 0.0;  // arc length where pieces[k] begins
  const int frames = static_cast<int>(std::floor(total / style.step_m + 1e-9)) + 1;
  for (int f = 0; f < frames; ++f) {
    const double s = f * style.step_m;  // from the index: no accumulated rounding
    while (k + 1 < pieces.size() && s > piece_start + pieces[k].length) {
      piece_start += pieces[k].length;
      ++k;
    }
    Eigen::Vector2d p;
    double yaw;
    pieces[k].at(s - piece_start, p, yaw);
    t.T_world_cam.push_back(level_pose(Eigen::Vector3d(p.x(), 0.0, p.y()), wrap(yaw)));
  }
  return t;
}

// Grid intersections (column, row) -> metres (x east, z north).
std::vector<Eigen::Vector2d> grid_route(const std::vector<std::pair<int, int>>& nodes,
                                        double block_x_m, double block_z_m) {
  std::vector<Eigen::Vector2d> out;
  for (const auto& [col, row] : nodes) out.emplace_back(col * block_x_m, row * block_z_m);
  return out;
}

Trajectory make_city() {
  // A 3 x 2 block grid (120 m x 100 m blocks). First a loop around the two western blocks, then
  // north through the middle, around the eastern side, west along the southern street (its
  // middle block was driven eastwards at the start: opposite direction), north again and east
  // along the middle street (driven westwards in the first loop). ~2 km.
  return sample_route("city", grid_route({{0, 0},
                                          {2, 0},
                                          {2, 1},
                                          {0, 1},
                                          {0, 0},
                                          {1, 0},
                                          {1, 2},
                                          {3, 2},
                                          {3, 0},
                                          {1, 0},
                                          {1, 1},
                                          {2, 1},
                                          {2, 2}},
                                         120.0, 100.0));
}

Trajectory make_short() {
  // One 80 m x 60 m block driven once and then its first street again: ~350 m.
  return sample_route("short",
                      grid_route({{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0, 0}, {1, 0}}, 80.0, 60.0));
}

Trajectory make_reverse() {
  // East along a 200 m street, around the block to the north, then the street's western
  // half again westwards: 100 m of reverse revisits in the other lane. ~520 m.
  return sample_route("reverse",
                      grid_route({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 0}, {0, 0}}, 100.0, 60.0));
}

Trajectory make_highway() {
  // An open road at highway speed (25 m/s at 10 frames/s): 600 m straight, a long bend of
  // 600 m radius to the east and back, ~1.7 km, driven once. No junctions: the camera keeps to
  // the road's axis (its lanes are WorldConfig's markings).
  RouteStyle style;
  style.lane_offset_m = 0.0;
  style.right_radius_m = style.left_radius_m = 600.0;
  style.step_m = 2.5;
  return sample_route("highway", {{0.0, 0.0}, {0.0, 600.0}, {300.0, 1100.0}, {300.0, 1700.0}},
                      style);
}

}  // namespace

std::vector<std::string> builtin_trajectory_names() {
  return {"city", "short", "reverse", "highway"};
}

Trajectory make_builtin_trajectory(const std::string& name) {
  if (name == "city") return make_city();
  if (name == "short") return make_short();
  if (name == "reverse") return make_reverse();
  if (name == "highway") return make_highway();
  std::string names;
  for (const std::string& n : builtin_trajectory_names()) names += (names.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown built-in trajectory '" + name + "'; known: " + names);
}

}  // namespace loopscan::sim
