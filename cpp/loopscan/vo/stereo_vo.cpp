#include "loopscan/vo/stereo_vo.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <unordered_map>
#include <utility>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "loopscan/core/rigid_motion.hpp"
#include "loopscan/core/timing.hpp"
#include "loopscan/vo/pose_refinement.hpp"

namespace loopscan::vo {
namespace {

using Clock = std::chrono::steady_clock;

double rotation_deg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.linear().transpose() * b.linear()).angle() * 180.0 / M_PI;
}

Eigen::Isometry3d from_rvec_tvec(const cv::Mat& rvec, const cv::Mat& tvec) {
  return rigid_motion({rvec.at<double>(0), rvec.at<double>(1), rvec.at<double>(2)},
                      {tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2)});
}

bool project(const StereoIntrinsics& c, const Eigen::Vector3d& p, cv::Point2f& px) {
  if (p.z() <= 0.1) return false;
  px = cv::Point2f(static_cast<float>(c.fx * p.x() / p.z() + c.cx),
                   static_cast<float>(c.fy * p.y() / p.z() + c.cy));
  return px.x >= 0 && px.y >= 0 && px.x <= c.width - 1 && px.y <= c.height - 1;
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// The nearest rigid motion (the rotation part re-orthonormalised).
Eigen::Isometry3d rigid(const Eigen::Isometry3d& T) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = Eigen::Quaterniond(T.linear()).normalized().toRotationMatrix();
  out.translation() = T.translation();
  return out;
}

}  // namespace

std::vector<IdPoint> world_points(const FinishedKeyframe& kf) {
  std::vector<IdPoint> out;
  out.reserve(kf.camera_points.size());
  for (const CameraPoint& p : kf.camera_points)
    out.push_back({kf.frame, kf.T_world_cam * p.p_cam, p.gray});
  return out;
}

StereoVo::StereoVo(const StereoIntrinsics& camera, const VoConfig& config)
    : camera_(camera), config_(config), px_scale_(pixel_scale(camera)) {
  if (!camera.plausible())
    throw std::invalid_argument(
        "StereoVo: implausible camera: expected a positive image size, focal lengths in [1, 1e5] "
        "px, a principal point within +-1e5 px and a baseline in (0, 100] m");
  if (config.window_keyframes < 2 || config.fixed_keyframes < 1)
    throw std::invalid_argument("StereoVo: the window needs >= 2 keyframes, >= 1 of them fixed");
}

FrameResult StereoVo::process(int frame, const cv::Mat& left, const cv::Mat& right) {
  if (closed_) throw std::logic_error("StereoVo::process after finish()");
  if (left.type() != CV_8UC1 || right.type() != CV_8UC1 || left.size() != right.size() ||
      left.cols != camera_.width || left.rows != camera_.height) {
    throw std::invalid_argument(
        "StereoVo: frame " + std::to_string(frame) + ": expected two 8-bit gray images of " +
        std::to_string(camera_.width) + "x" + std::to_string(camera_.height));
  }
  FrameResult r;
  r.frame = frame;
  auto t0 = Clock::now();
  const cv::Size window(config_.klt_window_px, config_.klt_window_px);
  std::vector<cv::Mat> pyramid;
  cv::buildOpticalFlowPyramid(left, pyramid, window, config_.klt_levels);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  if (!started_) {
    started_ = true;
    times_.track += ms_since(t0);
    add_keyframe(frame, left, right, T, false);
    r.keyframe = true;
  } else {
    // Tracking starts from the pose and points before the adjustment started at the previous
    // keyframe (it runs meanwhile); the pose is then estimated against the adjusted map. The
    // adjustment always lands here, whatever the threads' timing, so the result is fixed.
    Eigen::Isometry3d predicted = last_pose_ * velocity_;
    bool posed;
    if (!motion_known_) {  // one keyframe so far: no adjustment to wait for
      posed = track_from_standstill(pyramid, T, r);
      times_.track += ms_since(t0);
    } else {
      const bool tracked = track(predicted, pyramid, r);
      times_.track += ms_since(t0);
      const Eigen::Isometry3d correction = apply_window_ba();  // may drop tracks it rejects
      predicted = correction * predicted;
      last_pose_ = correction * last_pose_;
      r.tracked = static_cast<int>(tracks_.size());
      t0 = Clock::now();
      posed = tracked && r.tracked >= config_.min_inliers && estimate_pose(T, r);
      times_.pose += ms_since(t0);
    }
    motion_known_ = motion_known_ || posed;
    if (!posed) {
      // Explicit reset: bridge with the motion model, rebuild the map from this stereo pair.
      T = predicted;
      r.reset = true;
      resets_.push_back(frame);
      while (!window_.empty()) finish_oldest();
      tracks_.clear();
      add_keyframe(frame, left, right, T, true);
      r.keyframe = true;
    } else if (needs_keyframe(T, r.inliers)) {
      add_keyframe(frame, left, right, T, false);
      r.keyframe = true;
    }
    // Re-orthonormalised: through consecutive resets the bridge composes it frame after
    // frame, and the adjustment's corrections leave it slightly off a rotation.
    velocity_ = rigid(last_pose_.inverse() * T);
  }
  last_pose_ = T;
  previous_pyramid_ = std::move(pyramid);
  previous_left_ = left.clone();  // the caller may reuse its buffer
  const Keyframe& kf = window_.back();
  anchors_.push_back({kf.index, kf.T_world_cam.inverse() * T});
  r.T_world_cam = T;
  return r;
}

bool StereoVo::track(const Eigen::Isometry3d& predicted, const std::vector<cv::Mat>& pyramid,
                     FrameResult& r) {
  if (tracks_.empty()) return false;
  // A surface approached at speed grows between frames (by 25 % at 12 m and 2.5 m a frame), and
  // Lucas-Kanade's translation-only patch then slides off. Each track is followed from the
  // previous image scaled by its predicted growth (z before / z after), rounded to steps of
  // kScaleStep: the patch then matches up to a translation.
  constexpr double kScaleStep = 1.12;
  constexpr int kMinStep = -3, kMaxStep = 6;
  const Eigen::Isometry3d T_cam_world = predicted.inverse();
  const Eigen::Isometry3d T_previous_world = last_pose_.inverse();
  std::map<int, std::vector<std::size_t>> by_step;
  std::vector<cv::Point2f> guesses(tracks_.size());
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    const Track& t = tracks_[i];
    const Eigen::Vector3d now = T_cam_world * map_[t.point];
    cv::Point2f guess;
    guesses[i] = project(camera_, now, guess) ? guess : t.px;
    const double before = (T_previous_world * map_[t.point]).z();
    const double growth = before > 0.1 && now.z() > 0.1 ? before / now.z() : 1.0;
    const int step = std::clamp(
        static_cast<int>(std::lround(std::log(growth) / std::log(kScaleStep))), kMinStep, kMaxStep);
    by_step[step].push_back(i);
  }
  const cv::Size window(config_.klt_window_px, config_.klt_window_px);
  const cv::TermCriteria stop(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 0.01);
  const double max_fb = config_.forward_backward_px * px_scale_;
  std::vector<bool> good(tracks_.size(), false);
  std::vector<cv::Point2f> tracked(tracks_.size());
  for (const auto& [step, members] : by_step) {
    const double scale = std::pow(kScaleStep, step);
    // The scaled image keeps the image's size (OpenCV tracks between equal sizes): the scaling
    // is about the point that takes the members' previous positions onto their predictions
    // (least squares), so that they stay inside it.
    Eigen::Vector2d shift = Eigen::Vector2d::Zero();
    for (std::size_t i : members)
      shift += Eigen::Vector2d(guesses[i].x - scale * tracks_[i].px.x,
                               guesses[i].y - scale * tracks_[i].px.y);
    shift /= static_cast<double>(members.size());
    std::vector<cv::Mat> scaled_pyramid;
    if (step != 0) {
      const cv::Matx23d warp(scale, 0, shift.x(), 0, scale, shift.y());
      cv::Mat scaled;
      cv::warpAffine(previous_left_, scaled, warp, previous_left_.size(), cv::INTER_LINEAR,
                     cv::BORDER_REPLICATE);
      cv::buildOpticalFlowPyramid(scaled, scaled_pyramid, window, config_.klt_levels);
    }
    const std::vector<cv::Mat>& from = step != 0 ? scaled_pyramid : previous_pyramid_;
    const auto to_scaled = [&](const cv::Point2f& p) {
      return step == 0 ? p
                       : cv::Point2f(static_cast<float>(scale * p.x + shift.x()),
                                     static_cast<float>(scale * p.y + shift.y()));
    };
    std::vector<cv::Point2f> previous, current;
    for (std::size_t i : members) {
      previous.push_back(to_scaled(tracks_[i].px));
      current.push_back(guesses[i]);
    }
    std::vector<uchar> status, back_status;
    std::vector<float> error;
    cv::calcOpticalFlowPyrLK(from, pyramid, previous, current, status, error, window,
                             config_.klt_levels, stop, cv::OPTFLOW_USE_INITIAL_FLOW);
    std::vector<cv::Point2f> back = previous;
    cv::calcOpticalFlowPyrLK(pyramid, from, current, back, back_status, error, window,
                             config_.klt_levels, stop, cv::OPTFLOW_USE_INITIAL_FLOW);
    for (std::size_t k = 0; k < members.size(); ++k) {
      const cv::Point2f& p = current[k];
      if (!status[k] || !back_status[k] || cv::norm(back[k] - previous[k]) > max_fb * scale)
        continue;
      if (p.x < 0 || p.y < 0 || p.x > camera_.width - 1 || p.y > camera_.height - 1) continue;
      good[members[k]] = true;
      tracked[members[k]] = p;
    }
  }
  std::vector<Track> kept;
  for (std::size_t i = 0; i < tracks_.size(); ++i)
    if (good[i]) kept.push_back({tracks_[i].point, tracked[i]});
  tracks_ = std::move(kept);
  r.tracked = static_cast<int>(tracks_.size());
  return r.tracked >= config_.min_inliers;
}

bool StereoVo::track_from_standstill(const std::vector<cv::Mat>& pyramid, Eigen::Isometry3d& T,
                                     FrameResult& r) {
  // Tracking from a standstill follows a periodic structure (guard rail posts every 2 m,
  // fences) to its nearest copy and locks the VO onto a fraction of its speed; near structure
  // at speed is lost. Forward motions up to 4 m a frame (40 m/s at 10 Hz) in steps of 0.5 m,
  // a quarter of that period: the one whose pose keeps most tracks wins (ties: more tracks of
  // any kind, then the slower). Tracks vote only where their image is not self-similar along
  // the direction forward motion moves them (away from the principal point): those agree with
  // any speed. With fewer such tracks than min_inliers all vote.
  const std::vector<Track> start = tracks_;
  std::vector<int> decisive, everyone;  // point ids
  const cv::Point2f centre(static_cast<float>(camera_.cx), static_cast<float>(camera_.cy));
  for (const Track& t : start) {
    everyone.push_back(t.point);
    const cv::Point2f away = t.px - centre;
    if (std::hypot(away.x, away.y) > 1 && !self_similar_along(previous_left_, t.px, away))
      decisive.push_back(t.point);
  }
  if (static_cast<int>(decisive.size()) < config_.min_inliers) decisive = std::move(everyone);
  std::sort(decisive.begin(), decisive.end());
  auto score = [&] {  // (votes, inliers)
    int votes = 0;
    for (const Track& t : tracks_)
      votes += std::binary_search(decisive.begin(), decisive.end(), t.point) ? 1 : 0;
    return std::make_pair(votes, static_cast<int>(tracks_.size()));
  };
  std::pair<int, int> best(-1, -1);
  std::vector<Track> best_tracks;
  FrameResult best_result = r;
  for (int step = 0; step <= 8; ++step) {
    tracks_ = start;
    FrameResult attempt = r;
    Eigen::Isometry3d pose;
    const Eigen::Isometry3d guess = last_pose_ * Eigen::Translation3d(0.0, 0.0, 0.5 * step);
    if (!track(guess, pyramid, attempt) || !estimate_pose(pose, attempt)) continue;
    const std::pair<int, int> votes = score();  // tracks_ now holds the pose's inliers
    if (votes <= best) continue;
    best = votes;
    best_tracks = tracks_;
    best_result = attempt;
    T = pose;
  }
  tracks_ = std::move(best_tracks);
  r = best_result;
  r.tracked = static_cast<int>(tracks_.size());
  return best.first >= 0;
}

bool StereoVo::estimate_pose(Eigen::Isometry3d& T, FrameResult& r) {
  std::vector<cv::Point3d> object;
  std::vector<cv::Point2d> image;
  for (const Track& t : tracks_) {
    const Eigen::Vector3d& p = map_[t.point];
    object.emplace_back(p.x(), p.y(), p.z());
    image.emplace_back(t.px.x, t.px.y);
  }
  const cv::Matx33d K(camera_.fx, 0, camera_.cx, 0, camera_.fy, camera_.cy, 0, 0, 1);
  const double threshold = config_.ransac_reprojection_px * px_scale_;
  cv::Mat rvec, tvec;
  std::vector<int> inliers;
  const bool ok = cv::solvePnPRansac(object, image, K, cv::noArray(), rvec, tvec, false,
                                     config_.ransac_iterations, static_cast<float>(threshold),
                                     0.999, inliers, cv::SOLVEPNP_AP3P);
  if (!ok || static_cast<int>(inliers.size()) < config_.min_inliers) return false;
  // The inliers' pose with each weighted by its point's stereo uncertainty seen from here.
  Eigen::Isometry3d T_cam_world = from_rvec_tvec(rvec, tvec);
  std::vector<UncertainPoint> points;
  std::vector<Eigen::Vector2d> observations;
  for (int i : inliers) {
    points.push_back({map_[tracks_[i].point], map_covariance_[tracks_[i].point]});
    observations.emplace_back(tracks_[i].px.x, tracks_[i].px.y);
  }
  PoseRefinementConfig refinement;
  refinement.sigma_px = config_.track_sigma_px * px_scale_;
  if (!refine_pose(T_cam_world, points, observations, camera_, refinement)) return false;
  std::vector<Track> kept;
  for (const Track& t : tracks_) {
    cv::Point2f px;
    if (project(camera_, T_cam_world * map_[t.point], px) && cv::norm(px - t.px) < threshold)
      kept.push_back(t);
  }
  r.inliers = static_cast<int>(kept.size());
  if (r.inliers < config_.min_inliers) return false;
  T = T_cam_world.inverse();
  // Written to refuse a non-finite pose too (a degenerate refinement).
  if (!T.matrix().allFinite() ||
      !((T.translation() - last_pose_.translation()).norm() <= config_.max_step_m))
    return false;
  tracks_ = std::move(kept);
  return true;
}

bool StereoVo::needs_keyframe(const Eigen::Isometry3d& T, int inliers) const {
  const Keyframe& kf = window_.back();
  return (T.translation() - kf.T_world_cam.translation()).norm() > config_.keyframe_distance_m ||
         rotation_deg(kf.T_world_cam, T) > config_.keyframe_rotation_deg ||
         inliers < config_.keyframe_min_track_ratio * keyframe_tracks_;
}

double StereoVo::right_u(const cv::Mat& left, const cv::Mat& right, float u, float v) const {
  const StereoSearch search =
      stereo_search_for(camera_, config_, config_.min_depth_m, config_.max_depth_m, true);
  const double d = match_disparity(left, right, static_cast<int>(std::lround(u)),
                                   static_cast<int>(std::lround(v)), search);
  return std::isfinite(d) && d > 0 ? u - d : kNaN;
}

void StereoVo::add_keyframe(int frame, const cv::Mat& left, const cv::Mat& right,
                            Eigen::Isometry3d& T, bool reset) {
  auto t0 = Clock::now();
  Keyframe kf{frame, T, reset, keyframes_++, {}, {}};
  std::vector<cv::Point2f> occupied;
  for (const Track& t : tracks_) {
    kf.observations.push_back({t.point, t.px.x, t.px.y, right_u(left, right, t.px.x, t.px.y)});
    occupied.push_back(t.px);
  }
  const StereoSearch search =
      stereo_search_for(camera_, config_, config_.min_depth_m, config_.max_depth_m, true);
  for (const cv::Point2f& c : detect_grid_corners(left, occupied, config_)) {
    const double d = match_disparity(left, right, static_cast<int>(std::lround(c.x)),
                                     static_cast<int>(std::lround(c.y)), search);
    if (!std::isfinite(d) || d <= 0) continue;
    const int id = static_cast<int>(map_.size());
    map_.push_back(T * back_project(camera_, c.x, c.y, d));
    // Kept from the triangulation: the window's adjustment refines the point but its
    // covariance stays this (conservative) one.
    const Eigen::Matrix3d covariance =
        stereo_point_covariance(camera_, c.x, c.y, d, config_.track_sigma_px * px_scale_,
                                config_.stereo_sigma_px * px_scale_);
    map_covariance_.push_back(T.linear() * covariance * T.linear().transpose());
    tracks_.push_back({id, c});
    kf.observations.push_back({id, c.x, c.y, c.x - d});
  }
  times_.keyframe += ms_since(t0);
  // The exported points need neither poses nor tracks: off the tracking thread, on copies (the
  // caller may reuse its image buffers once process() returns).
  kf.camera_points = std::async(std::launch::async, [l = left.clone(), r = right.clone(),
                                                     camera = camera_, config = config_] {
    const auto start = Clock::now();
    std::vector<CameraPoint> points = select_gradient_points(l, r, camera, config);
    return std::make_pair(std::move(points), ms_since(start));
  });
  window_.push_back(std::move(kf));
  final_keyframe_poses_.push_back(T);
  start_window_ba();  // applied after the next frame's tracking (or by finish())
  keyframe_tracks_ = static_cast<int>(tracks_.size());
}

// The keyframe window's bundle adjustment: the last keyframes' poses and the points they share
// refined together, then the observations the optimum does not explain dropped.
void StereoVo::start_window_ba() {
  ba_.problem.reset();
  if (window_.size() < 2) return;
  auto problem = std::make_unique<BaProblem>();
  const int n = static_cast<int>(window_.size());
  ba_.n_fixed = std::min(config_.fixed_keyframes, n - 1);
  // Points constrained in depth: seen twice in the window or once with a right-image match.
  ba_.weight.clear();
  ba_.local.clear();
  for (const Keyframe& kf : window_)
    for (const Observation& o : kf.observations)
      ba_.weight[o.point] += std::isfinite(o.u_right) ? 2 : 1;
  for (int i = 0; i < n; ++i) {
    problem->T_cam_world.push_back(window_[i].T_world_cam.inverse());
    problem->fixed.push_back(i < ba_.n_fixed);
    for (const Observation& o : window_[i].observations) {
      if (ba_.weight[o.point] < 2) continue;
      auto [it, inserted] =
          ba_.local.try_emplace(o.point, static_cast<int>(problem->points.size()));
      if (inserted) problem->points.push_back(map_[o.point]);
      problem->observations.push_back({i, it->second, o.u, o.v, o.u_right});
    }
  }
  if (problem->observations.empty()) return;
  // Until it is applied nothing it reads changes: track() and estimate_pose() touch neither
  // the window nor the map, only tracks_.
  auto solve = [p = problem.get(), camera = camera_, iterations = config_.ba_iterations,
                huber = config_.ba_huber_px * px_scale_] {
    const auto t0 = StageClock::now();
    bundle_adjust(*p, camera, iterations, huber);
    return ms_since(t0);
  };
  ba_.problem = std::move(problem);
  ba_.done = std::async(config_.ba_on_worker ? std::launch::async : std::launch::deferred, solve);
}

Eigen::Isometry3d StereoVo::apply_window_ba() {
  Eigen::Isometry3d correction = Eigen::Isometry3d::Identity();
  if (ba_.problem) {
    const auto t0 = StageClock::now();
    times_.bundle_adjustment += ba_.done.get();
    if (config_.ba_on_worker) times_.ba_wait += ms_since(t0);
    const BaProblem& problem = *ba_.problem;
    const int n = static_cast<int>(window_.size());
    const Eigen::Isometry3d before = window_.back().T_world_cam;
    for (int i = ba_.n_fixed; i < n; ++i) {
      window_[i].T_world_cam = problem.T_cam_world[i].inverse();
      final_keyframe_poses_[window_[i].index] = window_[i].T_world_cam;
    }
    correction = window_.back().T_world_cam * before.inverse();
    for (const auto& [id, index] : ba_.local) map_[id] = problem.points[index];
    // Drop observations the optimum does not explain; a current track among them is dropped
    // too.
    const double max_error = 2.0 * config_.ransac_reprojection_px * px_scale_;
    std::unordered_map<int, bool> bad_current;
    std::size_t k = 0;
    for (int i = 0; i < n; ++i) {
      std::vector<Observation> kept;
      for (const Observation& o : window_[i].observations) {
        if (ba_.weight[o.point] < 2) {
          kept.push_back(o);
          continue;
        }
        const bool bad =
            reprojection_error(problem, problem.observations[k++], camera_) > max_error;
        if (!bad) kept.push_back(o);
        if (bad && i == n - 1) bad_current[o.point] = true;
      }
      window_[i].observations = std::move(kept);
    }
    if (!bad_current.empty()) {
      std::vector<Track> kept;
      for (const Track& t : tracks_)
        if (!bad_current.count(t.point)) kept.push_back(t);
      keyframe_tracks_ -= static_cast<int>(tracks_.size() - kept.size());
      tracks_ = std::move(kept);
    }
    ba_.problem.reset();
  }
  while (static_cast<int>(window_.size()) > config_.window_keyframes) finish_oldest();
  return correction;
}

void StereoVo::finish_oldest() {
  Keyframe& kf = window_.front();
  auto [points, ms] = kf.camera_points.get();
  times_.export_points += ms;
  finished_.push_back({kf.frame, kf.T_world_cam, kf.reset, std::move(points)});
  window_.erase(window_.begin());
}

void StereoVo::finish() {
  closed_ = true;
  apply_window_ba();
  while (!window_.empty()) finish_oldest();
}

std::vector<Eigen::Isometry3d> StereoVo::trajectory() const {
  std::vector<Eigen::Isometry3d> out;
  out.reserve(anchors_.size());
  for (const FrameAnchor& a : anchors_)
    out.push_back(final_keyframe_poses_[a.keyframe] * a.T_kf_frame);
  return out;
}

}  // namespace loopscan::vo
