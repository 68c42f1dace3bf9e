// Temporal consistency of verified loops (LoopCloser's members).
#include <cmath>

#include "loopscan/closure/loop_closer.hpp"
#include "loopscan/closure/pose_math.hpp"

namespace loopscan::closure {

using detail::isometry;
using detail::rotation_angle;

// The loop of an earlier keyframe p (to place mp) predicts this one's: T_q_m =
// T_q_p (odometry) * T_p_mp (its loop) * T_mp_m (the map's odometry).
bool LoopCloser::consistent(const Verified& earlier, const Loop& loop,
                            std::size_t place_index) const {
  const auto map_pose = [&](std::size_t i) { return isometry(*db_.pose(i)).inverse(); };
  if (!db_.pose(place_index) || !db_.pose(earlier.place_index)) return false;
  if (db_.place(place_index).session != db_.place(earlier.place_index).session) return false;
  const Eigen::Isometry3d T_q_p =
      vo_T_world_cam(loop.query).inverse() * vo_T_world_cam(earlier.loop.query);
  const Eigen::Isometry3d T_mp_m = map_pose(earlier.place_index).inverse() * map_pose(place_index);
  const Eigen::Isometry3d predicted = T_q_p * earlier.loop.T_query_match * T_mp_m;
  const Eigen::Isometry3d diff = predicted.inverse() * loop.T_query_match;
  return diff.translation().norm() <= config_.consistency.max_translation_m &&
         rotation_angle(diff.rotation()) <= config_.consistency.max_rotation_deg * M_PI / 180.0;
}

// Keeps the verified loop among the recent ones; returns the loops this confirms (itself and
// the earlier ones it agrees with), or nothing while too few agree.
std::vector<Loop> LoopCloser::confirm(const Loop& loop, std::size_t place_index) {
  while (!recent_.empty() &&
         described_ - recent_.front().described_at >= config_.consistency.window) {
    recent_.pop_front();
  }
  std::vector<Verified*> agreeing;
  for (Verified& v : recent_) {
    if (consistent(v, loop, place_index)) agreeing.push_back(&v);
  }
  recent_.push_back({loop, place_index, described_, false});
  std::vector<Loop> confirmed;
  if (int(agreeing.size()) + 1 < config_.consistency.required) return confirmed;
  agreeing.push_back(&recent_.back());
  for (Verified* v : agreeing) {
    if (v->in_graph) continue;
    v->in_graph = true;
    confirmed.push_back(v->loop);
  }
  return confirmed;
}

}  // namespace loopscan::closure
