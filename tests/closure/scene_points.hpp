#pragma once
// Point clouds of small street scenes in a camera frame (x right, y down, z forward): a ground
// plane, facades with recesses, poles and parked boxes, sampled at random; and the corridor that
// leaves the along-street translation free.
#include <cmath>
#include <random>
#include <vector>

#include "loopscan/closure/voxel_cloud.hpp"

namespace loopscan::test {

struct SceneOptions {
  bool poles_and_boxes = true;  // false: a bare corridor (facades and ground only)
  bool facade_recesses = true;  // windows / doors set back into the facades
  int points = 20000;
  double length_m = 70;  // along z, centred on the camera
  double half_width_m = 9;
};

inline closure::Points3f street_scene(unsigned seed, const SceneOptions& o = {}) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  struct Pole { double x, z, r; };
  struct Box { double x0, x1, z0, z1, h; };
  std::vector<Pole> poles;
  std::vector<Box> boxes;
  if (o.poles_and_boxes) {
    for (int i = 0; i < 14; ++i) {
      const double side = u(rng) < 0.5 ? -1 : 1;
      poles.push_back({side * (o.half_width_m - 1.5 - u(rng) * 1.5),
                       (u(rng) - 0.5) * o.length_m, 0.15 + 0.2 * u(rng)});
    }
    for (int i = 0; i < 8; ++i) {
      const double side = u(rng) < 0.5 ? -1 : 1;
      const double x = side * (o.half_width_m - 4.0), z = (u(rng) - 0.5) * o.length_m;
      boxes.push_back({x - 0.9, x + 0.9, z - 2.2, z + 2.2, 1.2 + 0.4 * u(rng)});
    }
  }
  const double ground_y = 1.65;
  closure::Points3f pts;
  // Windows and doors set back into the facades, irregular along the street (a facade bay of
  // 4 m has one or not, of its own width) so that no shift of whole bays fits again.
  std::vector<double> bay_start(64), bay_width(64);
  for (std::size_t i = 0; i < bay_start.size(); ++i) {
    bay_start[i] = u(rng) < 0.35 ? 9.0 : 0.3 + 1.2 * u(rng);  // 9: no window in this bay
    bay_width[i] = 0.8 + 1.8 * u(rng);
  }
  const auto recess = [&](double z, double y) {  // depth of the facade at (z, height)
    if (!o.facade_recesses) return 0.0;
    const double zz = z + 1000.0;
    const std::size_t bay = std::size_t(std::floor(zz / 4.0)) % bay_start.size();
    const double zm = zz - 4.0 * std::floor(zz / 4.0), ym = std::fmod(-y + ground_y + 100.0, 3.0);
    const bool window = zm > bay_start[bay] && zm < bay_start[bay] + bay_width[bay];
    return (window && ym > 0.9 && ym < 2.4) ? 0.35 : 0.0;
  };
  while (int(pts.size()) < o.points) {
    const double pick = u(rng);
    const double z = (u(rng) - 0.5) * o.length_m;
    if (pick < 0.35) {  // ground
      pts.emplace_back(float((u(rng) - 0.5) * 2 * o.half_width_m), float(ground_y), float(z));
    } else if (pick < 0.75) {  // facades, 10 m high
      const double side = u(rng) < 0.5 ? -1 : 1;
      const double y = ground_y - 10.0 * u(rng);
      pts.emplace_back(float(side * (o.half_width_m + recess(z * side, y))), float(y), float(z));
    } else if (pick < 0.88 && !poles.empty()) {
      const Pole& p = poles[std::size_t(u(rng) * poles.size())];
      const double a = u(rng) * 2 * M_PI;
      pts.emplace_back(float(p.x + p.r * std::cos(a)), float(ground_y - 5.0 * u(rng)),
                       float(p.z + p.r * std::sin(a)));
    } else if (!boxes.empty()) {
      const Box& b = boxes[std::size_t(u(rng) * boxes.size())];
      const double f = u(rng);
      const double y = ground_y - b.h * u(rng);
      if (f < 0.5) {
        pts.emplace_back(float(u(rng) < 0.5 ? b.x0 : b.x1), float(y), float(b.z0 + (b.z1 - b.z0) * u(rng)));
      } else {
        pts.emplace_back(float(b.x0 + (b.x1 - b.x0) * u(rng)), float(y), float(u(rng) < 0.5 ? b.z0 : b.z1));
      }
    }
  }
  return pts;
}

// Applies T and isotropic Gaussian noise of `sigma` metres.
inline closure::Points3f transformed(const closure::Points3f& pts, const Eigen::Isometry3d& T,
                                     double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> n(0.f, float(sigma));
  closure::Points3f out;
  out.reserve(pts.size());
  const Eigen::Matrix3f R = T.linear().cast<float>();
  const Eigen::Vector3f t = T.translation().cast<float>();
  for (const Eigen::Vector3f& p : pts) {
    out.push_back(R * p + t + Eigen::Vector3f(n(rng), n(rng), n(rng)));
  }
  return out;
}

}  // namespace loopscan::test
