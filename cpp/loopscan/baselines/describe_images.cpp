#include "loopscan/baselines/describe_images.hpp"

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "loopscan/core/parallel.hpp"
#include "loopscan/core/timing.hpp"
#include "loopscan/vo/image_file.hpp"

namespace loopscan::baselines {
namespace {

using Clock = std::chrono::steady_clock;

cv::Mat left_image(const io::KittiSequence& s, int frame, double& read_ms) {
  if (frame < 0 || static_cast<std::size_t>(frame) >= s.frames())
    throw std::invalid_argument("keyframe " + std::to_string(frame) + " is not a frame of " +
                                s.dir + " (" + std::to_string(s.frames()) + " frames)");
  const auto t0 = Clock::now();
  cv::Mat m = vo::read_gray_image(s.left(static_cast<std::size_t>(frame)));
  read_ms += ms_since(t0);
  return m;
}

void per_image(ImageDescriptors& d, std::size_t n) {
  if (n == 0) return;
  d.read_ms /= n;
  d.extract_ms /= n;
  d.transform_ms /= n;
  d.mean_features /= n;
}

}  // namespace

ImageDescriptors describe_gist(const io::KittiSequence& sequence, const std::vector<int>& frames,
                               const GistConfig& config, int threads, const ProgressFn& progress) {
  ImageDescriptors d;
  d.gist.resize(frames.size());
  threads = std::max(1, std::min<int>(threads, static_cast<int>(frames.size())));
  std::vector<double> read_ms(threads, 0.0), extract_ms(threads, 0.0);
  // One extractor (FFT plans, buffers) per thread; frames split round-robin.
  run_on_threads(threads, [&](int t) {
    GistExtractor gist(config);
    for (std::size_t i = t; i < frames.size(); i += threads) {
      const cv::Mat image = left_image(sequence, frames[i], read_ms[t]);
      const auto t0 = Clock::now();
      d.gist[i] = gist.describe(image);
      extract_ms[t] += ms_since(t0);
      report_worker_progress(progress, t, i + threads, frames.size());
    }
  });
  report_progress(progress, frames.size(), frames.size());
  for (int t = 0; t < threads; ++t) {
    d.read_ms += read_ms[t];
    d.extract_ms += extract_ms[t];
  }
  per_image(d, frames.size());
  return d;
}

ImageDescriptors describe_bow(const io::KittiSequence& sequence, const std::vector<int>& frames,
                              const Vocabulary& vocabulary, const OrbConfig& config,
                              const ProgressFn& progress) {
  ImageDescriptors d;
  for (int f : frames) {
    const cv::Mat image = left_image(sequence, f, d.read_ms);
    auto t0 = Clock::now();
    const cv::Mat orb = extract_orb(image, config);
    d.extract_ms += ms_since(t0);
    d.mean_features += orb.rows;
    t0 = Clock::now();
    d.bow.push_back(vocabulary.transform(orb));
    d.transform_ms += ms_since(t0);
    report_progress(progress, d.bow.size(), frames.size());
  }
  per_image(d, frames.size());
  return d;
}

std::vector<cv::Mat> orb_of_sequence(const io::KittiSequence& sequence, int step,
                                     const OrbConfig& config) {
  std::vector<cv::Mat> out;
  double unused = 0;
  for (std::size_t f = 0; f < sequence.frames(); f += static_cast<std::size_t>(std::max(1, step)))
    out.push_back(extract_orb(left_image(sequence, static_cast<int>(f), unused), config));
  return out;
}

}  // namespace loopscan::baselines
