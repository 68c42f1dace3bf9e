#include "loopscan/core/database/lane_query.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_set>

namespace loopscan {

std::vector<Candidate> query_with_lane_versions(const Database& db, const PlaceDescriptor& place,
                                                const std::vector<PlaceDescriptor>& lane_versions,
                                                int k, const QueryOptions& options,
                                                const LaneQueryOptions& lanes) {
  if (lane_versions.empty()) return db.query(place, k, options);
  const int per_version = std::max(k, lanes.candidates_per_version);
  // The lane versions exist in the camera frame only, where a mirrored match is impossible.
  std::vector<Candidate> all;
  for (const Candidate& c : db.query(place, per_version, options)) {
    if (!c.mirrored) all.push_back(c);
  }
  for (const PlaceDescriptor& version : lane_versions) {
    for (const Candidate& c : db.query(version, per_version, options)) {
      const double off_reverse = std::abs(std::remainder(c.yaw_rad - M_PI, 2.0 * M_PI));
      if (!c.mirrored && off_reverse < lanes.reverse_window_rad) all.push_back(c);
    }
  }
  std::stable_sort(all.begin(), all.end(),
                   [](const Candidate& a, const Candidate& b) { return a.distance < b.distance; });
  std::vector<Candidate> out;
  std::unordered_set<std::size_t> seen;
  for (const Candidate& c : all) {
    if (static_cast<int>(out.size()) >= k) break;
    if (seen.insert(c.index).second) out.push_back(c);
  }
  return out;
}

}  // namespace loopscan
