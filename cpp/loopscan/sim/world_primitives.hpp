#pragma once
// Geometric primitives of the synthetic world and their ray intersections. World frame is
// camera-like: x and z horizontal, y down, so a primitive's top has the smaller y.
#include <Eigen/Core>

namespace loopscan::sim {

// Box standing upright, rotated about the vertical axis. Local axes in (x, z): u = (cos, sin),
// v = (-sin, cos).
struct Box {
  double cx = 0.0, cz = 0.0;
  double cos_yaw = 1.0, sin_yaw = 0.0;
  double half_u = 0.5, half_v = 0.5;
  double y_top = -1.0, y_bottom = 0.0;  // y_top < y_bottom
};

// Faces of a Box as returned by intersect_box: axis * 2 + (1 if the max side).
enum BoxFace : int { kMinusU = 0, kPlusU = 1, kTop = 2, kBottom = 3, kMinusV = 4, kPlusV = 5 };

struct Cylinder {  // vertical, with flat caps
  double cx = 0.0, cz = 0.0, radius = 0.1;
  double y_top = -1.0, y_bottom = 0.0;
};

struct Ellipsoid {  // spheroid with a vertical axis (a sphere when radius_h == radius_v)
  double cx = 0.0, cy = 0.0, cz = 0.0;
  double radius_h = 1.0, radius_v = 1.0;
};

Box make_box(double cx, double cz, double yaw, double half_u, double half_v, double y_top,
             double y_bottom);

// Box coordinates (u, v) of a world point (x, z).
inline void box_local(const Box& b, double x, double z, double& u, double& v) {
  const double dx = x - b.cx, dz = z - b.cz;
  u = dx * b.cos_yaw + dz * b.sin_yaw;
  v = -dx * b.sin_yaw + dz * b.cos_yaw;
}

// First surface crossing at 0 <= t < t_max of the ray o + t d (the exit if o is inside).
bool intersect_box(const Box& b, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double t_max,
                   double& t, int& face);
bool intersect_cylinder(const Cylinder& c, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                        double t_max, double& t, bool& cap);
// Chord [t0, t1] of the ray inside the ellipsoid; false if missed or entirely behind (t1 < 0).
bool intersect_ellipsoid(const Ellipsoid& e, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                         double& t0, double& t1);

// Horizontal (x, z) outline of an object: an oriented rectangle, or a disc.
struct Footprint {
  double cx = 0.0, cz = 0.0;
  double cos_yaw = 1.0, sin_yaw = 0.0, half_u = 0.0, half_v = 0.0;
  double radius = 0.0;
  bool disc = false;
};

Footprint box_footprint(const Box& b);
Footprint disc_footprint(double cx, double cz, double radius);
// Axis-aligned bounds (min_x, min_z, max_x, max_z).
Eigen::Vector4d footprint_bounds(const Footprint& f);
// Horizontal distance from the footprint (0 if touching) to the segment a-b in (x, z).
double footprint_segment_distance(const Footprint& f, double ax, double az, double bx, double bz);
// True if the footprints come closer than `margin` (negative margin tolerates slight overlap).
bool footprints_overlap(const Footprint& a, const Footprint& b, double margin);

}  // namespace loopscan::sim
