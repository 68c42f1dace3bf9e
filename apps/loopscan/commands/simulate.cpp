// loopscan simulate: a synthetic world and what a stereo VO exports driving through it.
#include <cstdio>
#include <stdexcept>

#include "cli/commands.hpp"
#include "cli/configuration.hpp"
#include "cli/options.hpp"
#include "cli/output_sets.hpp"
#include "loopscan/io/sodso.hpp"
#include "outputs/simulation.hpp"

namespace loopscan::cli {
namespace {

struct SimulateArgs {
  ConfigFlags config;
  std::string trajectory, vo_poses, season = "summer", out, calib;
  unsigned seed = 1, session = 0;
  int laps = 1;
  std::vector<int> resets;
};

void run_simulate(const SimulateArgs& a) {
  const Configuration c = resolve_configuration(a.config);
  LoadedTrajectory t = load_trajectory(a.trajectory, c.simulator.world);
  if (a.laps > 1 && !a.vo_poses.empty())
    throw std::invalid_argument("--vo-poses gives the VO of one drive: use it without --laps");
  const std::vector<KeyframePose> vo_poses =
      a.vo_poses.empty() ? std::vector<KeyframePose>{} : io::read_sodso_poses(a.vo_poses);
  // The world is built along one lap and the way back to its start; every lap drives it.
  std::vector<Eigen::Vector3d> streets = t.trajectory.centres();
  if (a.laps > 1) {
    for (const Eigen::Isometry3d& T : sim::connector_back_to_start(t.trajectory))
      streets.push_back(T.translation());
    t.trajectory = sim::drive_laps(t.trajectory, a.laps);
    t.gps = false;  // the connector has no GPS rows: ground truth is written as poses
  }
  sim::WorldConfig wc = c.simulator.world;
  wc.seed = a.seed;
  std::printf("building the world along %zu frames ...\n", streets.size());
  const sim::World world = sim::World::build(streets, wc);
  sim::Conditions conditions = simulated_conditions(c, sim::parse_season(a.season));
  conditions.session_seed = a.session != 0 ? a.session : a.seed;
  const sim::StereoCamera camera = load_camera(a.calib);
  sim::VoSimConfig vo = c.simulator.vo;
  vo.seed = conditions.noise_seed(a.seed);
  vo.reset_keyframe_ids = a.resets;
  const Session s = simulate_session(t, world, conditions, camera, vo, vo_poses);
  write_session(a.out, t, s);
  write_used_configuration(a.out, c);
  std::printf("%s, %s: %zu keyframes, %zu points (%.0f per keyframe), %zu world objects -> %s\n",
              t.trajectory.name.c_str(), a.season.c_str(), s.keyframe_ids.size(),
              s.vo.points.size(), s.vo.mean_points_per_keyframe, world.object_count(),
              shown(a.out).c_str());
}

}  // namespace

void add_simulate_command(CLI::App& app) {
  auto a = std::make_shared<SimulateArgs>();
  CLI::App* cmd =
      app.add_subcommand("simulate", "Simulate a stereo VO's output in a synthetic world");
  cmd->add_option("--trajectory", a->trajectory,
                  "builtin:city | builtin:short | builtin:reverse | builtin:highway | kitti:FILE | "
                  "robotcar:FILE")
      ->required();
  cmd->add_option("--vo-poses", a->vo_poses, "SO-DSO poses_history_file.txt to use as VO poses");
  cmd->add_option("--season", a->season, "spring | summer | fall | winter")->capture_default_str();
  cmd->add_option("--seed", a->seed, "world seed (the same world for every season)")
      ->capture_default_str();
  cmd->add_option("--session", a->session, "session seed: parked cars, VO noise (default: seed)");
  cmd->add_option("--calib", a->calib, "ORB-SLAM2 KITTI yaml (default: KITTI 04-12 camera)");
  cmd->add_option("--laps", a->laps,
                  "drive the route this many times (a connector back to its start between laps)")
      ->check(finite_in(1, 1000))
      ->capture_default_str();
  cmd->add_option("--resets", a->resets, "keyframe ids where the VO restarts")
      ->check(finite_in(0, kMaxCount))
      ->delimiter(',');
  add_config_option(*cmd, a->config);
  cmd->add_option("--out", a->out, "output directory")->required();
  run_writing_dir(cmd, a, run_simulate);
}

}  // namespace loopscan::cli
