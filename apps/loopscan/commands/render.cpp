// loopscan render: rectified stereo images of the synthetic world in the KITTI odometry layout
// (image_0/, image_1/ as NNNNNN.png, calib.txt, times.txt, poses.txt).
#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <future>
#include <sstream>

#include "cli/commands.hpp"
#include "cli/configuration.hpp"
#include "cli/options.hpp"
#include "cli/output_sets.hpp"
#include "cli/progress.hpp"
#include "loopscan/io/atomic_file.hpp"
#include "loopscan/io/limits.hpp"
#include "loopscan/io/png.hpp"
#include "loopscan/io/vo_files.hpp"
#include "loopscan/sim/renderer.hpp"
#include "outputs/simulation.hpp"

namespace loopscan::cli {
namespace {

struct RenderArgs {
  ConfigFlags config;
  std::string trajectory, season = "summer", out, calib;
  unsigned seed = 1, session = 0;
  double scale = 1.0;
  int frames = -1, first = 0, threads = 2;
};

std::string calib_text(const sim::StereoCamera& c) {
  // KITTI: P0 = K [I | 0], P1 = K [I | -b e_x] (fourth column -fx * b = -bf).
  std::ostringstream s;
  s.precision(12);
  for (int i = 0; i < 4; ++i) {
    const double tx = (i % 2 == 1) ? -c.bf : 0.0;
    s << 'P' << i << ": " << c.fx << " 0 " << c.cx << ' ' << tx << " 0 " << c.fy << ' ' << c.cy
      << " 0 0 0 1 0\n";
  }
  return s.str();
}

void run_render(const RenderArgs& a) {
  if (a.scale <= 0 || a.scale > 4) throw std::invalid_argument("--scale must be in (0, 4]");
  const Configuration c = resolve_configuration(a.config);
  const LoadedTrajectory t = load_trajectory(a.trajectory, c.simulator.world);
  sim::WorldConfig wc = c.simulator.world;
  wc.seed = a.seed;
  const sim::World world = sim::World::build(t.trajectory.centres(), wc);
  sim::Conditions conditions = simulated_conditions(c, sim::parse_season(a.season));
  conditions.session_seed = a.session != 0 ? a.session : a.seed;
  const sim::StereoCamera camera = sim::scaled_camera(load_camera(a.calib), a.scale);
  if (std::int64_t(camera.width) * camera.height > io::limits::kMaxImagePixels) {
    throw std::invalid_argument("--scale " + std::to_string(a.scale) + " makes " +
                                std::to_string(camera.width) + "x" + std::to_string(camera.height) +
                                " images; at most " + std::to_string(io::limits::kMaxImagePixels) +
                                " pixels");
  }
  const int total = static_cast<int>(t.trajectory.T_world_cam.size());
  const int first = std::clamp(a.first, 0, total);
  const int count = a.frames < 0 ? total - first : std::min(a.frames, total - first);
  sim::RenderConfig rc = c.simulator.render;
  rc.seed = conditions.noise_seed(a.seed);
  rc.threads = std::max(1, a.threads);
  namespace fs = std::filesystem;
  fs::create_directories(a.out + "/image_0");
  fs::create_directories(a.out + "/image_1");
  StepProgress progress("render", "stereo pairs");
  std::vector<Eigen::Matrix<double, 3, 4>> poses;
  std::ostringstream times;
  // The PNGs of a pair (zlib, ~25 ms each) are written on another thread while the next pair
  // renders; the files are the same, each still written to a temporary file and renamed.
  std::future<void> writing;
  for (int i = 0; i < count; ++i) {
    const int f = first + i;
    char name[32];
    std::snprintf(name, sizeof name, "/%06d.png", i);
    std::array<sim::GrayImage, 2> pair;
    for (int cam = 0; cam < 2; ++cam)
      pair[cam] =
          sim::render_view(world, conditions, camera, t.trajectory.T_world_cam[f], cam, f, rc);
    if (writing.valid()) writing.get();  // rethrows a failed write
    writing =
        std::async(std::launch::async, [&a, name = std::string(name), pair = std::move(pair)] {
          for (int cam = 0; cam < 2; ++cam)
            io::write_png_gray(a.out + "/image_" + std::to_string(cam) + name, pair[cam].width,
                               pair[cam].height, pair[cam].pixels);
        });
    poses.push_back(t.trajectory.T_world_cam[f].matrix().topRows<3>());
    times << std::scientific << 0.1 * i << '\n';
    progress.update(std::size_t(i + 1), std::size_t(count));
  }
  if (writing.valid()) writing.get();
  progress.finish();
  io::write_file_atomic(a.out + "/calib.txt", calib_text(camera));
  io::write_file_atomic(a.out + "/times.txt", times.str());
  io::write_kitti_poses(a.out + "/poses.txt", poses);
  write_used_configuration(a.out, c);
  std::printf("%s, %s: %d stereo pairs of %dx%d -> %s\n", t.trajectory.name.c_str(),
              a.season.c_str(), count, camera.width, camera.height, shown(a.out).c_str());
}

}  // namespace

void add_render_command(CLI::App& app) {
  auto a = std::make_shared<RenderArgs>();
  CLI::App* cmd = app.add_subcommand(
      "render", "Render stereo images of the synthetic world (KITTI odometry layout)");
  cmd->add_option("--trajectory", a->trajectory,
                  "builtin:city | builtin:short | builtin:reverse | builtin:highway | kitti:FILE | "
                  "robotcar:FILE")
      ->required();
  cmd->add_option("--season", a->season, "spring | summer | fall | winter")->capture_default_str();
  cmd->add_option("--seed", a->seed, "world seed")->capture_default_str();
  cmd->add_option("--session", a->session, "session seed: parked cars, noise (default: seed)");
  cmd->add_option("--scale", a->scale, "image scale (1: 1241x376)")
      ->check(finite_in(0.01, 4))
      ->capture_default_str();
  cmd->add_option("--first", a->first, "first trajectory frame")
      ->check(finite_in(0, kMaxCount))
      ->capture_default_str();
  cmd->add_option("--frames", a->frames, "number of frames (default: all)")
      ->check(finite_in(0, kMaxCount));
  cmd->add_option("--calib", a->calib, "ORB-SLAM2 KITTI yaml (default: KITTI 04-12 camera)");
  cmd->add_option("--threads", a->threads, "render threads")
      ->check(finite_in(1, kMaxThreads))
      ->capture_default_str();
  add_config_option(*cmd, a->config);
  cmd->add_option("--out", a->out, "output directory")->required();
  run_writing_dir(cmd, a, run_render);
}

}  // namespace loopscan::cli
