#pragma once
// Recognising a street driven the other way, in the other lane. A Scan Context described at
// the keyframe does not match the reverse drive 3.5 m to the side
// (docs/experiments/direction-lane-season.md); the same scan described from where a car in the
// neighbouring lane would be (ScanContextConfig::lateral_offset_m, camera frame) does. Those
// lane versions are queried too, and their candidates count only when the place is seen the
// other way round: yaw within a window of 180 degrees, unmirrored.
#include <vector>

#include "loopscan/core/database/database.hpp"

namespace loopscan {

struct LaneQueryOptions {
  double reverse_window_rad = 20.0 * M_PI / 180.0;  // |yaw - pi| below this
  int candidates_per_version = 10;  // best places of each version checked (yaw, mirror)
};

// Candidates of `place` (any yaw) and of its lane versions (reverse yaw only), merged by
// distance, one per database place, best `k` first. Without versions: db.query(place, k, ...).
// Throws like Database::query.
std::vector<Candidate> query_with_lane_versions(const Database& db, const PlaceDescriptor& place,
                                                const std::vector<PlaceDescriptor>& lane_versions,
                                                int k, const QueryOptions& options,
                                                const LaneQueryOptions& lanes = {});

}  // namespace loopscan
