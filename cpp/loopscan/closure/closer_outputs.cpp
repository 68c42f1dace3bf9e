// What a LoopCloser hands back: corrected poses, the corrected map, re-expressed points.
#include <unordered_map>

#include "loopscan/closure/loop_closer.hpp"
#include "loopscan/closure/pose_math.hpp"

namespace loopscan::closure {

using detail::isometry;

std::vector<KeyframePose> LoopCloser::corrected_poses() const {
  std::vector<KeyframePose> out;
  out.reserve(input_poses_.size());
  for (std::size_t i = 0; i < input_poses_.size(); ++i) {
    KeyframePose k;
    k.id = input_poses_[i].id;
    k.T_cam_world = graph_.pose(graph_node_[i]).inverse().matrix().topRows<3>();
    out.push_back(k);
  }
  return out;
}

Database LoopCloser::corrected_map() const {
  Database out(db_.config());
  std::vector<float> payload(std::size_t(db_.payload_floats()));
  for (std::size_t i = 0; i < db_.size(); ++i) {
    const PlaceRef p = db_.place(i);
    std::optional<Pose3x4> pose = db_.pose(i);
    if (p.session == config_.recognition.session) {
      pose = graph_.pose(graph_node_[pose_index_.at(p.keyframe)]).inverse().matrix().topRows<3>();
    }
    db_.stored_payload(i, payload.data());
    out.add_stored(p, payload.data(), db_.frame(i), pose);
  }
  return out;
}

std::vector<IdPoint> reexpress_points(const std::vector<IdPoint>& points,
                                      const std::vector<KeyframePose>& vo_poses,
                                      const std::vector<KeyframePose>& corrected) {
  std::unordered_map<int, Eigen::Isometry3d> correction;  // new T_world_cam * old T_cam_world
  std::unordered_map<int, const KeyframePose*> old;
  for (const KeyframePose& k : vo_poses) old[k.id] = &k;
  for (const KeyframePose& k : corrected) {
    const auto it = old.find(k.id);
    if (it == old.end()) continue;
    correction[k.id] = isometry(k.T_cam_world).inverse() * isometry(it->second->T_cam_world);
  }
  std::vector<IdPoint> out;
  out.reserve(points.size());
  for (const IdPoint& p : points) {
    const auto it = correction.find(p.id);
    if (it == correction.end()) continue;
    IdPoint q = p;
    q.p_world = it->second * p.p_world;
    out.push_back(q);
  }
  return out;
}

}  // namespace loopscan::closure
