#pragma once
// The local point cloud a place keeps for geometric verification of loops (closure/): points in
// the camera frame of the place's keyframe, those off the ground first. A plain value type here
// so that the database file can persist it without depending on the closure module.
#include <cstddef>
#include <vector>

#include <Eigen/Core>

namespace loopscan {

struct PlaceCloud {
  std::vector<Eigen::Vector3f> points;
  std::size_t structure = 0;  // points[0, structure) are off the ground
};

}  // namespace loopscan
