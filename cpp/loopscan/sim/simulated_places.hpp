#pragma once
// Described places of a simulated drive in one call: the tests (yaw against ground truth,
// online against offline) and the database benchmark start from it.
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "loopscan/core/database/database.hpp"
#include "loopscan/sim/conditions.hpp"
#include "loopscan/sim/trajectory.hpp"

namespace loopscan::sim {

struct SimulatedPlaces {
  std::vector<int> keyframe_ids;               // described keyframes (frame ids)
  std::vector<PlaceDescriptor> places;         // one per described keyframe
  std::vector<Eigen::Isometry3d> T_world_cam;  // ground truth of each described keyframe
  std::vector<Eigen::Vector3d> positions() const;
};

// Builds the world along `route` (world seed `seed`), drives it in `season` (session seed
// `session`) and describes every keyframe with `method` in default mode.
SimulatedPlaces simulate_places(const Trajectory& route, Season season, unsigned seed,
                                unsigned session, Method method, int threads = 1);

}  // namespace loopscan::sim
