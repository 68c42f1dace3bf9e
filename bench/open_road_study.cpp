// Study of the stereo VO where structure is mostly far away (docs/experiments/open-road.md):
// renders a drive of the simulator, measures the VO's stereo matches against the renderer's
// depth per depth band, then runs the VO and reports its odometry errors and Sim(3) scale.
//
//   loopscan_open_road_study [--world open-road|open-road-no-rails|city] [--route NAME] [--first F]
//   [--frames N]
//                            [--scale S] [--every K]
//
// Defaults: the open-road world along builtin:highway, 120 frames from 0, full KITTI size,
// stereo statistics at every 4th frame. --world city: the default street world.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/video/tracking.hpp>

#include "loopscan/eval/odometry_metrics.hpp"
#include "loopscan/sim/renderer.hpp"
#include "loopscan/sim/trajectory.hpp"
#include "loopscan/sim/world.hpp"
#include "loopscan/vo/image_points.hpp"
#include "loopscan/vo/stereo_vo.hpp"

namespace {

using namespace loopscan;

struct Options {
  std::string world = "open-road", route = "highway";
  int first = 0, frames = 120, every = 4;
  double scale = 1.0;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
      return argv[++i];
    };
    if (a == "--world") {
      o.world = value();
    } else if (a == "--route") {
      o.route = value();
    } else if (a == "--first") {
      o.first = std::stoi(value());
    } else if (a == "--frames") {
      o.frames = std::stoi(value());
    } else if (a == "--every") {
      o.every = std::max(1, std::stoi(value()));
    } else if (a == "--scale") {
      o.scale = std::stod(value());
    } else {
      throw std::invalid_argument("unknown option " + a);
    }
  }
  if (o.world != "open-road" && o.world != "open-road-no-rails" && o.world != "city")
    throw std::invalid_argument("--world: open-road, open-road-no-rails or city");
  return o;
}

cv::Mat to_mat(const sim::GrayImage& g) {
  return cv::Mat(g.height, g.width, CV_8UC1, const_cast<std::uint8_t*>(g.pixels.data())).clone();
}

vo::StereoIntrinsics intrinsics_of(const sim::StereoCamera& c) {
  vo::StereoIntrinsics k;
  k.fx = c.fx;
  k.fy = c.fy;
  k.cx = c.cx;
  k.cy = c.cy;
  k.baseline_m = c.baseline();
  k.width = c.width;
  k.height = c.height;
  return k;
}

// Errors of the matched disparities of one depth band (true depth in [lo, hi) m).
struct Band {
  double lo = 0, hi = 0;
  std::vector<double> error_px, depth_ratio;  // estimate - truth; estimated / true depth
  int unmatched = 0, wrong = 0;               // wrong: off by more than 2 px (not in error_px)
};

// Lucas-Kanade tracks of one depth band from a frame to the next, started at the true position
// (a perfect motion model), checked forwards-backwards as the VO checks them.
struct TrackBand {
  int corners = 0, kept = 0, wrong = 0;  // wrong: kept but more than 2 px from the truth
};

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? NAN : s / v.size();
}

double rms(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x * x;
  return v.empty() ? NAN : std::sqrt(s / v.size());
}

}  // namespace

int main(int argc, char** argv) try {
  const Options o = parse(argc, argv);
  const sim::Trajectory route = sim::make_builtin_trajectory(o.route);
  const int last = std::min<int>(o.first + o.frames, static_cast<int>(route.T_world_cam.size()));
  if (o.first < 0 || o.first >= last) throw std::invalid_argument("no frames in that range");
  sim::WorldConfig wc = o.world == "city" ? sim::WorldConfig{} : sim::open_road_world_config();
  wc.guard_rails = wc.guard_rails && o.world != "open-road-no-rails";
  const sim::World world = sim::World::build(route.centres(), wc);
  const sim::Conditions conditions = sim::Conditions::for_season(sim::Season::Summer);
  const sim::StereoCamera camera = sim::scaled_camera(sim::StereoCamera{}, o.scale);
  const vo::StereoIntrinsics k = intrinsics_of(camera);
  const vo::VoConfig config;
  sim::RenderConfig rc;
  rc.threads = 2;

  std::vector<Band> bands(4);
  const double edges[] = {0, 10, 20, 40, 80};
  for (std::size_t i = 0; i < bands.size(); ++i) {
    bands[i].lo = edges[i];
    bands[i].hi = edges[i + 1];
  }
  vo::StereoVo vo(k, config);
  std::vector<Eigen::Isometry3d> gt;
  const Eigen::Isometry3d T0 = route.T_world_cam[o.first];
  std::vector<TrackBand> track_bands(bands.size());
  int resets = 0;
  cv::Mat previous_left;
  std::vector<cv::Point2f> previous_corners, previous_truth;
  std::vector<std::size_t> previous_band;
  for (int f = o.first; f < last; ++f) {
    const Eigen::Isometry3d& T = route.T_world_cam[f];
    const cv::Mat left = to_mat(sim::render_view(world, conditions, camera, T, 0, f, rc));
    const cv::Mat right = to_mat(sim::render_view(world, conditions, camera, T, 1, f, rc));
    if (!previous_corners.empty()) {
      const cv::Size window(config.klt_window_px, config.klt_window_px);
      const cv::TermCriteria stop(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01);
      std::vector<cv::Point2f> current = previous_truth, back = previous_corners;
      std::vector<uchar> status, back_status;
      std::vector<float> error;
      cv::calcOpticalFlowPyrLK(previous_left, left, previous_corners, current, status, error,
                               window, config.klt_levels, stop, cv::OPTFLOW_USE_INITIAL_FLOW);
      cv::calcOpticalFlowPyrLK(left, previous_left, current, back, back_status, error, window,
                               config.klt_levels, stop, cv::OPTFLOW_USE_INITIAL_FLOW);
      for (std::size_t i = 0; i < current.size(); ++i) {
        TrackBand& b = track_bands[previous_band[i]];
        ++b.corners;
        if (!status[i] || !back_status[i] ||
            cv::norm(back[i] - previous_corners[i]) > config.forward_backward_px * o.scale)
          continue;
        ++b.kept;
        if (cv::norm(current[i] - previous_truth[i]) > 2.0 * o.scale) ++b.wrong;
      }
      previous_corners.clear();
    }
    if ((f - o.first) % o.every == 0) {
      // The VO's own corners and disparity search (its tracks' depths) against the truth.
      const std::vector<double> distance = sim::render_depth(world, conditions, camera, T, 0, rc);
      const bool next = f + 1 < last;
      const Eigen::Isometry3d next_from_this =
          next ? route.T_world_cam[f + 1].inverse() * T : Eigen::Isometry3d::Identity();
      previous_truth.clear();
      previous_band.clear();
      // The VO's search for its tracks' depths (left-right checked).
      const vo::StereoSearch search =
          vo::stereo_search_for(k, config, config.min_depth_m, config.max_depth_m, true);
      for (const cv::Point2f& c : vo::detect_grid_corners(left, {}, config)) {
        const int u = static_cast<int>(std::lround(c.x)), v = static_cast<int>(std::lround(c.y));
        const double along = distance[static_cast<std::size_t>(v) * camera.width + u];
        if (along <= 0) continue;  // sky
        const double z = along * camera.ray(u, v).z();
        const double truth = camera.bf / z;
        Eigen::Vector2d moved;
        const std::size_t band = static_cast<std::size_t>(
            std::upper_bound(std::begin(edges), std::end(edges), z) - std::begin(edges) - 1);
        if (next && band < bands.size() &&
            camera.project(next_from_this * (along * camera.ray(u, v)), moved)) {
          previous_corners.push_back(c);
          previous_truth.emplace_back(static_cast<float>(moved.x()), static_cast<float>(moved.y()));
          previous_band.push_back(band);
        }
        for (Band& b : bands) {
          if (z < b.lo || z >= b.hi) continue;
          const double d = vo::match_disparity(left, right, u, v, search);
          if (!std::isfinite(d)) {
            ++b.unmatched;
          } else if (std::abs(d - truth) > 2.0 * o.scale) {
            ++b.wrong;
          } else {
            b.error_px.push_back(d - truth);
            b.depth_ratio.push_back(truth / d);
          }
        }
      }
    }
    previous_left = left;
    resets += vo.process(f, left, right).reset ? 1 : 0;
    gt.push_back(T0.inverse() * T);
  }
  vo.finish();

  std::printf("%s world along builtin:%s, frames %d-%d (%.1f m), %dx%d\n", o.world.c_str(),
              o.route.c_str(), o.first, last - 1, eval::path_distances(gt).back(), camera.width,
              camera.height);
  std::printf("\nstereo matches of the VO's corners (every %d frames) against the renderer:\n\n",
              o.every);
  std::printf(
      "| true depth (m) | corners | matched | wrong (> 2 px) | disparity bias (px) | "
      "median abs. error (px) | RMS (px) | median depth error (%%) |\n"
      "| --- | --- | --- | --- | --- | --- | --- | --- |\n");
  for (const Band& b : bands) {
    std::vector<double> abs_error;
    for (double e : b.error_px) abs_error.push_back(std::abs(e));
    const std::size_t matched = b.error_px.size() + static_cast<std::size_t>(b.wrong);
    const std::size_t n = matched + static_cast<std::size_t>(b.unmatched);
    std::printf("| %.0f-%.0f | %zu | %.0f %% | %.1f %% | %+.3f | %.3f | %.3f | %+.2f |\n", b.lo,
                b.hi, n, n ? 100.0 * matched / n : 0.0, matched ? 100.0 * b.wrong / matched : 0.0,
                mean(b.error_px), median(abs_error), rms(b.error_px),
                100.0 * (median(b.depth_ratio) - 1.0));
  }
  std::printf(
      "\nLucas-Kanade tracks of those corners into the next frame, started at the true "
      "position, forward-backward checked:\n\n| true depth (m) | corners | kept | wrong "
      "(> 2 px) |\n| --- | --- | --- | --- |\n");
  for (std::size_t i = 0; i < bands.size(); ++i) {
    const TrackBand& t = track_bands[i];
    std::printf("| %.0f-%.0f | %d | %.0f %% | %.1f %% |\n", bands[i].lo, bands[i].hi, t.corners,
                t.corners ? 100.0 * t.kept / t.corners : 0.0,
                t.kept ? 100.0 * t.wrong / t.kept : 0.0);
  }
  eval::OdometryOptions oo;
  oo.segment_lengths_m = {10, 20, 30, 40};
  oo.step_frames = 1;
  const eval::OdometryMetrics m = eval::odometry_metrics(gt, vo.trajectory(), oo);
  std::printf(
      "\nVO: translation %.2f %% (10-40 m segments), rotation %.3f deg/100 m, ATE %.3f m, "
      "Sim(3) scale %.4f, ATE after Sim(3) %.3f m, %d resets\n",
      m.translation_percent, m.rotation_deg_per_100m, m.ate_rmse_m, m.sim3_scale, m.ate_sim3_rmse_m,
      resets);
  return 0;
} catch (const std::exception& e) {
  std::fprintf(stderr, "loopscan_open_road_study: %s\n", e.what());
  return 2;
}
