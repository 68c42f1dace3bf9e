#include "loopscan/vo/run_sequence.hpp"

#include <algorithm>
#include <chrono>
#include <future>

#include "loopscan/io/errors.hpp"
#include "loopscan/vo/image_file.hpp"

namespace loopscan::vo {
namespace {

using Clock = std::chrono::steady_clock;

struct StereoPair {
  cv::Mat left, right;
  double load_ms = 0;
};

StereoPair load_pair(const io::KittiSequence& s, int frame, bool blank,
                     const SequenceRunOptions& options) {
  const auto t0 = Clock::now();
  StereoPair p{read_gray_image(s.left(frame)), read_gray_image(s.right(frame))};
  if (p.left.size() != p.right.size())
    throw io::InputError(s.right(frame), 0, "right image size differs from the left image's");
  if (options.prepare_pair) options.prepare_pair(p.left, p.right);
  if (blank) {
    p.left.setTo(0);
    p.right.setTo(0);
  }
  p.load_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  return p;
}

}  // namespace

StereoIntrinsics intrinsics_of(const io::KittiSequence& sequence) {
  if (sequence.frames() == 0) throw io::InputError(sequence.dir, 0, "sequence has no frames");
  const cv::Mat first = read_gray_image(sequence.left(0));
  StereoIntrinsics c;
  c.fx = sequence.calib.fx;
  c.fy = sequence.calib.fy;
  c.cx = sequence.calib.cx;
  c.cy = sequence.calib.cy;
  c.baseline_m = sequence.calib.baseline_m;
  c.width = first.cols;
  c.height = first.rows;
  return c;
}

SequenceRun run_stereo_vo(const io::KittiSequence& sequence, const VoConfig& config,
                          const SequenceRunOptions& options) {
  SequenceRun run;
  run.camera = intrinsics_of(sequence);
  const int total = static_cast<int>(sequence.frames());
  const int first = std::clamp(options.first, 0, total);
  const int count = options.frames < 0 ? total - first : std::min(options.frames, total - first);
  auto blank = [&](int f) {
    return std::find(options.blank_frames.begin(), options.blank_frames.end(), f) !=
           options.blank_frames.end();
  };
  StereoVo vo(run.camera, config);
  const auto t0 = Clock::now();
  std::future<StereoPair> next;
  if (count > 0)
    next = std::async(std::launch::async, load_pair, std::cref(sequence), first, blank(first),
                      std::cref(options));
  for (int i = 0; i < count; ++i) {
    StereoPair pair = next.get();
    const int f = first + i;
    if (i + 1 < count)
      next = std::async(std::launch::async, load_pair, std::cref(sequence), f + 1, blank(f + 1),
                        std::cref(options));
    if (pair.left.cols != run.camera.width || pair.left.rows != run.camera.height) {
      throw io::InputError(sequence.left(f), 0,
                           "image size differs from the first frame's (" +
                               std::to_string(run.camera.width) + "x" +
                               std::to_string(run.camera.height) + ")");
    }
    run.load_ms += pair.load_ms;
    vo.process(f, pair.left, pair.right);
    run.frame_ids.push_back(f);
    if (options.progress) {
      const double s = std::chrono::duration<double>(Clock::now() - t0).count();
      options.progress(i + 1, count, (i + 1) / std::max(s, 1e-9));
    }
  }
  vo.finish();
  run.seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  run.fps = count / std::max(run.seconds, 1e-9);
  run.trajectory = vo.trajectory();
  run.keyframes = vo.finished_keyframes();
  run.reset_frames = vo.reset_frames();
  std::size_t n_points = 0;
  for (const FinishedKeyframe& kf : run.keyframes) {
    KeyframePose pose;
    pose.id = kf.frame;
    pose.T_cam_world = kf.T_world_cam.inverse().matrix().topRows<3>();
    run.keyframe_poses.push_back(pose);
    for (const IdPoint& p : world_points(kf)) run.points.push_back(p);
    n_points += kf.camera_points.size();
  }
  if (!run.keyframes.empty())
    run.mean_points_per_keyframe = double(n_points) / run.keyframes.size();
  const double n = std::max(count, 1);
  const StageTimes& s = vo.stage_times();
  run.stage_ms = {s.track / n, s.pose / n, s.keyframe / n, s.bundle_adjustment / n,
                  s.export_points / n};
  run.load_ms /= n;
  return run;
}

}  // namespace loopscan::vo
