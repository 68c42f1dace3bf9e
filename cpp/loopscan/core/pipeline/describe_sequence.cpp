#include "loopscan/core/pipeline/describe_sequence.hpp"

#include "loopscan/core/keyframe_stream.hpp"
#include "loopscan/core/parallel.hpp"
#include "loopscan/core/timing.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>

namespace loopscan {

SequenceOptions SequenceOptions::make(Method method, Mode mode, double range_m) {
  SequenceOptions o;
  o.method = method;
  o.imitation.mode = mode;
  o.imitation.range_m = range_m;
  o.descriptors = DescriptorConfig::for_mode(mode, range_m);
  return o;
}

namespace {

// Describes scans[i] into out[i], on `threads` threads; returns the summed milliseconds.
double describe_batch(const std::vector<Cloud>& scans, const SequenceOptions& options,
                      std::vector<Signature>& out, std::vector<Eigen::Matrix3d>& frames) {
  const int threads = std::max(1, std::min<int>(options.threads, static_cast<int>(scans.size())));
  std::vector<double> ms(threads, 0.0);
  auto work = [&](int t) {
    for (std::size_t i = t; i < scans.size(); i += threads) {
      const auto t0 = std::chrono::steady_clock::now();
      out[i] = describe(options.method, scans[i], options.descriptors, &frames[i]);
      ms[t] += ms_since(t0);
    }
  };
  run_on_threads(threads, work);
  double total = 0;
  for (double m : ms) total += m;
  return total;
}

}  // namespace

SequenceSignatures describe_sequence(const std::vector<KeyframePose>& poses,
                                     const std::vector<IdPoint>& points,
                                     const SequenceOptions& options) {
  if (options.threads < 1 || options.threads > SequenceOptions::kMaxThreads) {
    throw std::invalid_argument("describe_sequence: threads must be in [1, " +
                                std::to_string(SequenceOptions::kMaxThreads) + "], got " +
                                std::to_string(options.threads));
  }
  // The walk below hands each keyframe the points up to its id: both must be in id order (the
  // SO-DSO reader refuses other files; arrays from elsewhere are checked here).
  for (std::size_t k = 1; k < poses.size(); ++k) {
    if (poses[k].id <= poses[k - 1].id) {
      throw std::invalid_argument("describe_sequence: keyframe ids in increasing order (id " +
                                  std::to_string(poses[k].id) + " after " +
                                  std::to_string(poses[k - 1].id) + ")");
    }
  }
  const auto by_id = [](const IdPoint& a, const IdPoint& b) { return a.id < b.id; };
  if (!std::is_sorted(points.begin(), points.end(), by_id)) {
    throw std::invalid_argument("describe_sequence: point ids in non-decreasing order");
  }
  SequenceSignatures out;
  ScanImitator imitator(options.imitation);
  const ScanFilter filter = filter_for(options.method);
  std::vector<int> resets = options.reset_ids;
  std::sort(resets.begin(), resets.end());
  std::vector<Cloud> batch;  // scans waiting for their description
  const std::size_t batch_size = options.threads > 1 ? 16 * std::size_t(options.threads) : 1;
  auto flush = [&] {
    std::vector<Signature> sigs(batch.size());
    std::vector<Eigen::Matrix3d> frames(batch.size());
    out.describe_ms += describe_batch(batch, options, sigs, frames);
    for (Signature& s : sigs) out.signatures.push_back(std::move(s));
    out.frames.insert(out.frames.end(), frames.begin(), frames.end());
    batch.clear();
  };
  std::vector<ReadyScan> ready;
  auto take = [&] {  // scans of keyframes that are ready: into the batch
    for (ReadyScan& r : ready) {
      out.keyframe_ids.push_back(r.keyframe.id);
      out.mean_in_range += static_cast<double>(r.in_range.size());
      out.mean_filtered += static_cast<double>(r.scan.size());
      batch.push_back(std::move(r.scan));
      if (batch.size() >= batch_size) flush();
    }
    ready.clear();
  };
  std::size_t walked = 0;
  for_each_keyframe(
      poses, points, [&](const KeyframePose& keyframe, const IdPoint* first, std::size_t count) {
        const bool reset = std::binary_search(resets.begin(), resets.end(), keyframe.id);
        const auto t0 = std::chrono::steady_clock::now();
        imitator.push(keyframe, first, count, reset, filter, ready);
        out.imitate_ms += ms_since(t0);
        take();
        // The last keyframe is reported after the final descriptions, not before them.
        if (++walked < poses.size()) report_progress(options.progress, walked, poses.size());
      });
  const auto t0 = std::chrono::steady_clock::now();
  imitator.finish(filter, ready);
  out.imitate_ms += ms_since(t0);
  take();
  flush();
  report_progress(options.progress, poses.size(), poses.size());
  if (const double n = static_cast<double>(out.signatures.size()); n > 0) {
    out.imitate_ms /= n;
    out.describe_ms /= n;
    out.mean_in_range /= n;
    out.mean_filtered /= n;
  }
  return out;
}

std::vector<int> detect_vo_resets(const std::vector<KeyframePose>& poses, double jump_m) {
  std::vector<int> resets;
  for (std::size_t i = 1; i < poses.size(); ++i) {
    const Eigen::Vector3d c = camera_centre(poses[i].T_cam_world);
    if (c.norm() < 1.0 && (c - camera_centre(poses[i - 1].T_cam_world)).norm() > jump_m) {
      resets.push_back(poses[i].id);
    }
  }
  return resets;
}

}  // namespace loopscan
