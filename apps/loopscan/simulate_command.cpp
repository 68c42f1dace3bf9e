// loopscan simulate: a synthetic world and what a stereo VO exports driving through it.
#include <cstdio>

#include "commands.hpp"
#include "loopscan/io/sodso.hpp"
#include "options.hpp"
#include "output_sets.hpp"
#include "simulation_setup.hpp"

namespace loopscan::cli {
namespace {

struct SimulateArgs {
  std::string trajectory, vo_poses, season = "summer", out, calib;
  unsigned seed = 1, session = 0;
  double gain = -1, gamma = -1;  // < 0: the season's default
  sim::VoSimConfig vo;
  std::vector<int> resets;
};

void run_simulate(const SimulateArgs& args) {
  SimulateArgs a = args;
  const LoadedTrajectory t = load_trajectory(a.trajectory);
  const std::vector<KeyframePose> vo_poses =
      a.vo_poses.empty() ? std::vector<KeyframePose>{} : io::read_sodso_poses(a.vo_poses);
  sim::WorldConfig wc;
  wc.seed = a.seed;
  std::printf("building the world along %zu frames ...\n", t.trajectory.T_world_cam.size());
  const sim::World world = sim::World::build(t.trajectory.centres(), wc);
  sim::Conditions conditions = sim::Conditions::for_season(sim::parse_season(a.season));
  conditions.session_seed = a.session != 0 ? a.session : a.seed;
  if (a.gain >= 0) conditions.illumination_gain = a.gain;
  if (a.gamma > 0) conditions.gamma = a.gamma;
  const sim::StereoCamera camera = load_camera(a.calib);
  a.vo.seed = conditions.noise_seed(a.seed);
  a.vo.reset_keyframe_ids = a.resets;
  const Session s = simulate_session(t, world, conditions, camera, a.vo, vo_poses);
  write_session(a.out, t, s);
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
                  "builtin:city | builtin:short | kitti:FILE | robotcar:FILE")
      ->required();
  cmd->add_option("--vo-poses", a->vo_poses, "SO-DSO poses_history_file.txt to use as VO poses");
  cmd->add_option("--season", a->season, "spring | summer | fall | winter")->capture_default_str();
  cmd->add_option("--seed", a->seed, "world seed (the same world for every season)")
      ->capture_default_str();
  cmd->add_option("--session", a->session, "session seed: parked cars, VO noise (default: seed)");
  cmd->add_option("--gain", a->gain, "illumination gain (default: the season's)")
      ->check(finite_in(0, 100));
  cmd->add_option("--gamma", a->gamma, "illumination gamma (default: the season's)")
      ->check(finite_in(0.01, 10));
  cmd->add_option("--calib", a->calib, "ORB-SLAM2 KITTI yaml (default: KITTI 04-12 camera)");
  cmd->add_option("--points-per-keyframe", a->vo.points_per_keyframe,
                  "points the simulated VO exports per keyframe (SO-DSO-like density)")
      ->check(finite_in(1, 100000))
      ->capture_default_str();
  cmd->add_option("--disparity-sigma", a->vo.disparity_sigma_px, "stereo noise in px")
      ->check(finite_in(0, 100))
      ->capture_default_str();
  cmd->add_option("--drift", a->vo.drift_translation_per_m, "VO drift, m per m travelled")
      ->check(finite_in(0, 1))
      ->capture_default_str();
  cmd->add_option("--drift-rotation", a->vo.drift_rotation_deg_per_m, "VO drift, deg per m")
      ->check(finite_in(0, 90))
      ->capture_default_str();
  cmd->add_option("--resets", a->resets, "keyframe ids where the VO restarts")
      ->check(finite_in(0, kMaxCount))
      ->delimiter(',');
  cmd->add_option("--out", a->out, "output directory")->required();
  run_writing_dir(cmd, a, run_simulate);
}

}  // namespace loopscan::cli
