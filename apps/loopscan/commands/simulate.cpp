// loopscan simulate: a synthetic world and what a stereo VO exports driving through it.
#include <algorithm>
#include <cstdio>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

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

// "summer" or a season per lap, cycled: "summer,winter".
std::vector<std::string> lap_seasons(const std::string& list, int laps) {
  std::vector<std::string> seasons;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = list.find(',', start);
    seasons.push_back(list.substr(start, comma - start));
    sim::parse_season(seasons.back());  // throws naming a wrong one
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (seasons.size() > 1 && laps < 2)
    throw std::invalid_argument("--season: a list of seasons (one per lap) needs --laps");
  return seasons;
}

// Keyframe by keyframe, the points of the session whose season its lap has. Every session has
// the same keyframes and VO poses (the drift depends on the seeds, not the season).
Session merge_by_lap(std::map<std::string, Session> sessions,
                     const std::vector<std::string>& seasons, int laps, std::size_t route_frames,
                     std::size_t connector_frames) {
  auto season_of = [&](int frame) {
    // A connector belongs to the lap it leads into.
    const std::size_t f = static_cast<std::size_t>(frame);
    const std::size_t lap =
        f < route_frames ? 0 : 1 + (f - route_frames) / (route_frames + connector_frames);
    return seasons[lap % seasons.size()];
  };
  Session merged = sessions.at(seasons.front());
  merged.vo.points.clear();
  for (const auto& [season, session] : sessions)
    for (const IdPoint& p : session.vo.points)
      if (season_of(p.id) == season) merged.vo.points.push_back(p);
  std::stable_sort(merged.vo.points.begin(), merged.vo.points.end(),
                   [](const IdPoint& a, const IdPoint& b) { return a.id < b.id; });
  merged.vo.mean_points_per_keyframe =
      merged.keyframe_ids.empty()
          ? 0.0
          : static_cast<double>(merged.vo.points.size()) / merged.keyframe_ids.size();
  std::vector<std::string> by_lap;
  for (int lap = 0; lap < laps; ++lap) by_lap.push_back(seasons[lap % seasons.size()]);
  merged.parameters["conditions"]["season_by_lap"] = by_lap;
  merged.parameters["result"]["points"] = merged.vo.points.size();
  merged.parameters["result"]["mean_points_per_keyframe"] = merged.vo.mean_points_per_keyframe;
  return merged;
}

void run_simulate(const SimulateArgs& a) {
  const Configuration c = resolve_configuration(a.config);
  LoadedTrajectory t = load_trajectory(a.trajectory, c.simulator.world);
  if (a.laps > 1 && !a.vo_poses.empty())
    throw std::invalid_argument("--vo-poses gives the VO of one drive: use it without --laps");
  const std::vector<std::string> seasons = lap_seasons(a.season, a.laps);
  const std::vector<KeyframePose> vo_poses =
      a.vo_poses.empty() ? std::vector<KeyframePose>{} : io::read_sodso_poses(a.vo_poses);
  // The world is built along one lap and the way back to its start; every lap drives it.
  const std::vector<Eigen::Vector3d> streets = sim::lap_streets(t.trajectory, a.laps);
  const std::size_t route_frames = t.trajectory.T_world_cam.size();
  const std::size_t connector_frames = streets.size() - route_frames;
  if (a.laps > 1) {
    t.trajectory = sim::drive_laps(t.trajectory, a.laps);
    t.gps = false;  // the connector has no GPS rows: ground truth is written as poses
  }
  sim::WorldConfig wc = c.simulator.world;
  wc.seed = a.seed;
  std::printf("building the world along %zu frames ...\n", streets.size());
  const sim::World world = sim::World::build(streets, wc);
  const sim::StereoCamera camera = load_camera(a.calib);
  auto drive_in = [&](const std::string& season) {
    sim::Conditions conditions = simulated_conditions(c, sim::parse_season(season));
    conditions.session_seed = a.session != 0 ? a.session : a.seed;
    sim::VoSimConfig vo = c.simulator.vo;
    vo.seed = conditions.noise_seed(a.seed);
    vo.reset_keyframe_ids = a.resets;
    return simulate_session(t, world, conditions, camera, vo, vo_poses);
  };
  std::map<std::string, Session> by_season;
  for (const std::string& season : seasons)
    if (!by_season.count(season)) by_season.emplace(season, drive_in(season));
  const Session s = by_season.size() == 1 ? std::move(by_season.begin()->second)
                                          : merge_by_lap(std::move(by_season), seasons, a.laps,
                                                         route_frames, connector_frames);
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
  cmd->add_option("--season", a->season,
                  "spring | summer | fall | winter; with --laps a list cycled over the laps "
                  "(summer,winter)")
      ->capture_default_str();
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
