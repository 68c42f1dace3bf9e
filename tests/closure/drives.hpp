#pragma once
// Simulated drives for the loop-closer tests: a built-in route with a drifting VO, driven one
// or more laps, streamed keyframe by keyframe and scored against the ground truth.
#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include <gtest/gtest.h>

#include "loopscan/closure/loop_closer.hpp"
#include "loopscan/core/keyframe_stream.hpp"
#include "loopscan/eval/loop_metrics.hpp"
#include "loopscan/sim/trajectory.hpp"
#include "loopscan/sim/vo_simulator.hpp"
#include "loopscan/sim/world.hpp"

namespace loopscan::test {

struct Drive {
  sim::Trajectory route;
  sim::VoOutput vo;
};

// A built-in route driven `laps` times (the world built along one lap and the way back to its
// start) in world `wc`, simulated by `vo` (its seed drawn from the session's).
inline Drive drive_in(sim::Season season, unsigned session, const std::string& route, int laps,
                      const sim::WorldConfig& wc, sim::VoSimConfig vo) {
  const sim::Trajectory one_lap = sim::make_builtin_trajectory(route);
  Drive d{sim::drive_laps(one_lap, laps), {}};
  const sim::World world = sim::World::build(sim::lap_streets(one_lap, laps), wc);
  sim::Conditions conditions = sim::Conditions::for_season(season);
  conditions.session_seed = session;
  vo.seed = conditions.noise_seed(wc.seed);
  d.vo = sim::simulate_vo(d.route, sim::select_keyframes(d.route), world, conditions,
                          sim::StereoCamera{}, vo);
  return d;
}

// The default world and a drifting VO (default 1 %: `drift_per_m` metres and 3 x that in
// degrees a metre); the route by default the short one, a block and its first street again.
inline Drive drive(sim::Season season, unsigned session, const std::string& route = "short",
                   double drift_per_m = 0.02, int laps = 1) {
  sim::VoSimConfig vo;
  vo.drift_translation_per_m = drift_per_m;
  vo.drift_rotation_deg_per_m = 3 * drift_per_m;
  return drive_in(season, session, route, laps, {}, vo);
}

template <typename PerKeyframe>
void stream(const Drive& d, PerKeyframe&& f) {
  for_each_keyframe(d.vo.poses, d.vo.points, f);
}

// The drive with its VO restarted at keyframe index `at`: that keyframe and every later one,
// their poses and points, in a new frame whose origin is that keyframe's camera (as a VO that
// lost track and began again would give them).
inline Drive with_vo_reset(Drive d, std::size_t at) {
  const Eigen::Isometry3d T_new_world = closure::isometry(d.vo.poses.at(at).T_cam_world);
  const int before_id = at > 0 ? d.vo.poses[at - 1].id : -1;  // later points are the new run's
  for (std::size_t i = at; i < d.vo.poses.size(); ++i) {
    d.vo.poses[i].T_cam_world =
        (closure::isometry(d.vo.poses[i].T_cam_world) * T_new_world.inverse())
            .matrix()
            .topRows<3>();
  }
  for (IdPoint& p : d.vo.points) {
    if (p.id > before_id) p.p_world = T_new_world * p.p_world;
  }
  return d;
}

// The drive's ground-truth camera centres, one per keyframe.
inline std::vector<Eigen::Vector3d> truth(const Drive& d) {
  std::vector<Eigen::Vector3d> gt;
  for (const KeyframePose& k : d.vo.poses)
    gt.push_back(d.route.T_world_cam[std::size_t(k.id)].translation());
  return gt;
}

// A revisit: keyframe i within 10 m of one 100 or more keyframes earlier.
inline bool is_revisit(const std::vector<Eigen::Vector3d>& gt, std::size_t i) {
  for (std::size_t j = 0; j + 100 <= i; ++j) {
    if ((gt[i] - gt[j]).norm() <= 10.0) return true;
  }
  return false;
}

inline std::vector<Eigen::Vector3d> centres(const std::vector<KeyframePose>& poses) {
  std::vector<Eigen::Vector3d> out;
  for (const KeyframePose& k : poses) {
    out.push_back(camera_centre(k.T_cam_world));
  }
  return out;
}

struct Closed {
  double ate_before = 0, ate_after = 0;
  int revisits = 0, closed = 0, false_loops = 0;
  std::size_t map_places = 0, graph_nodes = 0, graph_edges = 0;
  std::vector<int> joined;       // keyframes whose place joined the map
  std::string false_list;        // query -> match (source, metres apart)
  std::vector<double> whitened;  // per accepted loop: |translation error| in its covariance
};

// Runs the closer over a drive and scores it against the ground truth (revisits: is_revisit).
// `reset_id`: the keyframe the VO restarted at (with_vo_reset), told to the closer.
inline Closed close_drive(const Drive& d, const closure::LoopCloserConfig& config,
                          int reset_id = -1) {
  closure::LoopCloser closer(config);
  Closed out;
  stream(d, [&](const KeyframePose& k, const IdPoint* p, std::size_t n) {
    const closure::KeyframeClosure c = closer.add_keyframe(k, p, n, k.id == reset_id);
    if (c.described && c.linked_place < 0) out.joined.push_back(k.id);
  });
  closer.finish();
  out.map_places = closer.database().size();
  out.graph_nodes = closer.times().graph_nodes;
  out.graph_edges = closer.times().graph_edges;
  const std::vector<Eigen::Vector3d> gt = truth(d);
  out.ate_before = eval::aligned_rmse(gt, centres(d.vo.poses));
  out.ate_after = eval::aligned_rmse(gt, centres(closer.corrected_poses()));
  std::set<int> closed_queries;
  for (const closure::Loop& l : closer.loops()) {
    if (!l.accepted()) continue;
    const Eigen::Isometry3d& q = d.route.T_world_cam[std::size_t(l.query)];
    const Eigen::Isometry3d& m = d.route.T_world_cam[std::size_t(l.match.keyframe)];
    const eval::LoopTruth t = eval::loop_truth(l.T_query_match, q, m);
    if (!t.is_true) {
      ++out.false_loops;
      out.false_list += std::to_string(l.query) + " -> " + std::to_string(l.match.keyframe) +
                        (l.nearby ? " (nearby, " : " (descriptor, ") +
                        std::to_string(t.gt_distance_m) + " m) ";
      continue;
    }
    closed_queries.insert(l.query);
    const Eigen::Vector3d error = l.T_query_match.translation() - (q.inverse() * m).translation();
    const Eigen::Matrix3d cov =
        closure::loop_covariance(l, config.loop_uncertainty).topLeftCorner<3, 3>();
    out.whitened.push_back(std::sqrt(error.dot(cov.ldlt().solve(error))));
  }
  for (std::size_t i = 0; i < d.vo.poses.size(); ++i) {
    const bool revisit = is_revisit(gt, i);
    out.revisits += revisit;
    out.closed += revisit && closed_queries.count(d.vo.poses[i].id);
  }
  return out;
}

// Two runs' verifications alike to the bit: query, place, verdict, overlap and pose.
inline ::testing::AssertionResult same_loops(const std::vector<closure::Loop>& a,
                                             const std::vector<closure::Loop>& b) {
  if (a.size() != b.size()) {
    return ::testing::AssertionFailure() << a.size() << " against " << b.size() << " loops";
  }
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].query != b[i].query || !(a[i].match == b[i].match) ||
        a[i].place_index != b[i].place_index || a[i].verdict != b[i].verdict ||
        a[i].overlap != b[i].overlap ||
        a[i].T_query_match.matrix() != b[i].T_query_match.matrix()) {
      return ::testing::AssertionFailure() << "verification " << i << " (query " << a[i].query
                                           << ") differs";
    }
  }
  return ::testing::AssertionSuccess();
}

// Two runs' place clouds alike to the bit: points and structure counts.
inline ::testing::AssertionResult same_clouds(const std::vector<PlaceCloud>& a,
                                              const std::vector<PlaceCloud>& b) {
  if (a.size() != b.size()) {
    return ::testing::AssertionFailure() << a.size() << " against " << b.size() << " clouds";
  }
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].structure != b[i].structure || !(a[i].points == b[i].points)) {
      return ::testing::AssertionFailure() << "place cloud " << i << " differs";
    }
  }
  return ::testing::AssertionSuccess();
}

// Two runs' corrected poses alike to the bit, ids included.
inline ::testing::AssertionResult same_poses(const std::vector<KeyframePose>& a,
                                             const std::vector<KeyframePose>& b) {
  if (a.size() != b.size()) {
    return ::testing::AssertionFailure() << a.size() << " against " << b.size() << " poses";
  }
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a[i].id != b[i].id || a[i].T_cam_world.matrix() != b[i].T_cam_world.matrix()) {
      return ::testing::AssertionFailure() << "pose " << i << " (keyframe " << a[i].id
                                           << ") differs";
    }
  }
  return ::testing::AssertionSuccess();
}

}  // namespace loopscan::test
