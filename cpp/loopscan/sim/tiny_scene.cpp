#include "loopscan/sim/tiny_scene.hpp"

#include <algorithm>
#include <cmath>
#include <random>

namespace loopscan::sim {
namespace {

// A facade sample: position on the street side, height and albedo drawn once per world.
struct Landmark {
  Eigen::Vector3d p;  // world: x east, y down, z north (camera-like, so the VO frame matches)
  float gray;
};

std::vector<Landmark> make_world(const TinySceneConfig& c, std::mt19937& rng) {
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::vector<Landmark> world;
  const double half = c.block_m / 2.0;
  // Buildings line both sides of the square road, with gaps and varying heights/setbacks.
  for (int side = 0; side < 4; ++side) {
    for (double s = -half - 15; s < half + 15; s += 4.0) {
      for (int outer = 0; outer < 2; ++outer) {
        if (u01(rng) < 0.15) continue;  // a gap between buildings
        const double setback = 6.0 + 4.0 * u01(rng);
        const double height = 4.0 + 14.0 * u01(rng);
        const double offset = outer ? half + setback : half - setback;
        const float albedo = static_cast<float>(40 + 180 * u01(rng));
        for (int k = 0; k < 40; ++k) {
          const double along = s + 4.0 * u01(rng), up = height * u01(rng);
          Eigen::Vector3d p;
          if (side == 0) p = {along, -up, -offset};
          if (side == 1) p = {offset, -up, along};
          if (side == 2) p = {-along, -up, offset};
          if (side == 3) p = {-offset, -up, -along};
          const float gray = std::min(255.f, albedo + static_cast<float>(30 * u01(rng)));
          world.push_back({p + Eigen::Vector3d(0, 1.6, 0), gray});  // camera 1.6 m above ground
        }
      }
    }
  }
  return world;
}

// Position and heading (yaw about the down axis) along the square route at arc length s.
void route_pose(const TinySceneConfig& c, double s, Eigen::Vector3d& pos, double& yaw) {
  const double half = c.block_m / 2.0, side_len = c.block_m;
  const double t = std::fmod(s, 4 * side_len);
  const int side = static_cast<int>(t / side_len);
  const double a = t - side * side_len - half;
  const Eigen::Vector3d start[4] = {
      {-half, 0, -half}, {half, 0, -half}, {half, 0, half}, {-half, 0, half}};
  const Eigen::Vector3d dir[4] = {{1, 0, 0}, {0, 0, 1}, {-1, 0, 0}, {0, 0, -1}};
  pos = start[side] + (a + half) * dir[side];
  yaw = std::atan2(dir[side].x(), dir[side].z());
}

}  // namespace

TinyScene make_tiny_scene(const TinySceneConfig& c) {
  std::mt19937 rng(c.seed);
  const std::vector<Landmark> world = make_world(c, rng);
  std::normal_distribution<double> noise(0.0, c.depth_noise_m);
  TinyScene scene;
  const int n = static_cast<int>(c.laps * 4 * c.block_m / c.keyframe_step_m);
  for (int id = 0; id < n; ++id) {
    Eigen::Vector3d pos;
    double yaw;
    route_pose(c, id * c.keyframe_step_m, pos, yaw);
    // Camera-to-world rotation: yaw about the down (y) axis; z forward along the road.
    Eigen::Matrix3d R_world_cam;
    R_world_cam << std::cos(yaw), 0, std::sin(yaw), 0, 1, 0, -std::sin(yaw), 0, std::cos(yaw);
    KeyframePose k;
    k.id = id;
    k.T_cam_world.leftCols<3>() = R_world_cam.transpose();
    k.T_cam_world.col(3) = -R_world_cam.transpose() * pos;
    scene.poses.push_back(k);
    scene.positions.push_back(pos);
    // Export a subset of the landmarks in the forward view, with depth noise.
    std::vector<const Landmark*> visible;
    for (const Landmark& l : world) {
      const Eigen::Vector3d pc = k.T_cam_world.leftCols<3>() * l.p + k.T_cam_world.col(3);
      if (pc.z() > 2.0 && pc.z() < c.view_depth_m && std::abs(pc.x()) < 0.9 * pc.z()) {
        visible.push_back(&l);
      }
    }
    std::shuffle(visible.begin(), visible.end(), rng);
    const std::size_t take = std::min<std::size_t>(visible.size(), c.points_per_keyframe);
    for (std::size_t i = 0; i < take; ++i) {
      const Eigen::Vector3d ray = visible[i]->p - pos;
      const Eigen::Vector3d p = pos + ray * (1.0 + noise(rng) / std::max(ray.norm(), 1.0));
      scene.points.push_back({id, p, visible[i]->gray});
    }
  }
  return scene;
}

}  // namespace loopscan::sim
