#include "loopscan/sim/simulated_places.hpp"

#include "loopscan/core/pipeline/describe_sequence.hpp"
#include "loopscan/sim/vo_simulator.hpp"
#include "loopscan/sim/world.hpp"

namespace loopscan::sim {

std::vector<Eigen::Vector3d> SimulatedPlaces::positions() const {
  std::vector<Eigen::Vector3d> out;
  for (const Eigen::Isometry3d& T : T_world_cam) out.push_back(T.translation());
  return out;
}

SimulatedPlaces simulate_places(const Trajectory& route, Season season, unsigned seed,
                                unsigned session, Method method, int threads) {
  WorldConfig wc;
  wc.seed = seed;
  const World world = World::build(route.centres(), wc);
  Conditions conditions = Conditions::for_season(season);
  conditions.session_seed = session;
  VoSimConfig vo;
  vo.seed = conditions.noise_seed(seed);
  const std::vector<int> keyframes = select_keyframes(route);
  const VoOutput out = simulate_vo(route, keyframes, world, conditions, StereoCamera{}, vo);
  SequenceOptions options = SequenceOptions::make(method, Mode::Default);
  options.threads = threads;
  SequenceSignatures sig = describe_sequence(out.poses, out.points, options);
  SimulatedPlaces p;
  p.keyframe_ids = sig.keyframe_ids;
  for (std::size_t i = 0; i < sig.signatures.size(); ++i) {
    p.places.push_back({std::move(sig.signatures[i]), sig.frames[i]});
    p.T_world_cam.push_back(route.T_world_cam[sig.keyframe_ids[i]]);
  }
  return p;
}

}  // namespace loopscan::sim
