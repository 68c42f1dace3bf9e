// Image-side stages at KITTI resolution (1241x376, rendered from the synthetic city): stereo VO
// per frame, GIST per image, ORB extraction (4000 features), BoW transform, and BoW queries
// through the inverted index against 5,000 images. One thread unless stated. On demand.
#include <algorithm>
#include <map>
#include <random>

#include <benchmark/benchmark.h>

#include "loopscan/baselines/gist.hpp"
#include "loopscan/baselines/inverted_index.hpp"
#include "loopscan/baselines/orb_features.hpp"
#include "loopscan/baselines/vocabulary.hpp"
#include "loopscan/sim/renderer.hpp"
#include "loopscan/sim/trajectory.hpp"
#include "loopscan/vo/stereo_vo.hpp"

namespace {

using namespace loopscan;

struct Frames {
  std::vector<cv::Mat> left, right;
  vo::StereoIntrinsics camera;
};

const Frames& frames() {
  static const Frames f = [] {
    Frames out;
    const sim::Trajectory route = sim::make_builtin_trajectory("city");
    const sim::World world = sim::World::build(route.centres(), sim::WorldConfig{});
    const sim::Conditions c = sim::Conditions::for_season(sim::Season::Summer);
    const sim::StereoCamera cam;
    sim::RenderConfig rc;
    rc.threads = 2;
    for (int i = 0; i < 24; ++i) {
      const int frame = 300 + i;  // a turn and a straight
      for (int side = 0; side < 2; ++side) {
        const sim::GrayImage g =
            sim::render_view(world, c, cam, route.T_world_cam[frame], side, frame, rc);
        cv::Mat m =
            cv::Mat(g.height, g.width, CV_8UC1, const_cast<std::uint8_t*>(g.pixels.data())).clone();
        (side == 0 ? out.left : out.right).push_back(m);
      }
    }
    out.camera.baseline_m = cam.baseline();
    return out;
  }();
  return f;
}

void BM_VoPerFrame(benchmark::State& state) {
  const Frames& f = frames();  // rendered before the timing starts
  for (auto _ : state) {
    vo::StereoVo odometry(f.camera);
    for (std::size_t i = 0; i < f.left.size(); ++i)
      benchmark::DoNotOptimize(odometry.process(static_cast<int>(i), f.left[i], f.right[i]));
  }
  state.counters["ms_per_frame"] = benchmark::Counter(
      static_cast<double>(state.iterations() * f.left.size()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert, benchmark::Counter::OneK::kIs1000);
}
BENCHMARK(BM_VoPerFrame)->Unit(benchmark::kMillisecond);

// Arg 0: the default variant (LMgist-like, 32 px mirrored border); 1: Lear's C GIST as the
// authors call it (cover + crop, filters on the 256 x 256 image itself).
void BM_Gist(benchmark::State& state) {
  frames();  // render outside the timing
  baselines::GistExtractor gist(state.range(0) == 1 ? baselines::GistConfig::lear_c()
                                                    : baselines::GistConfig{});
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(gist.describe(frames().left[i++ % 24]));
}
BENCHMARK(BM_Gist)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_OrbExtract(benchmark::State& state) {
  frames();
  std::size_t i = 0, n = 0;
  for (auto _ : state) n += baselines::extract_orb(frames().left[i++ % 24]).rows;
  state.counters["features"] = static_cast<double>(n) / state.iterations();
}
BENCHMARK(BM_OrbExtract)->Unit(benchmark::kMillisecond);

void BM_BowTransform(benchmark::State& state) {
  std::vector<cv::Mat> d;
  for (const cv::Mat& m : frames().left) d.push_back(baselines::extract_orb(m));
  baselines::VocabularyConfig vc;  // k 10, L 6
  const baselines::Vocabulary v = baselines::train_vocabulary(d, vc);
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(v.transform(d[i++ % d.size()]));
  state.counters["words"] = static_cast<double>(v.words());
}
BENCHMARK(BM_BowTransform)->Unit(benchmark::kMillisecond);

// ORB-SLAM2's setting: ~10^6 words, ~4000 features -> ~2,500 distinct words an image, word
// frequencies following Zipf's law.
baselines::BowVector zipf_bow(std::mt19937& rng, const std::vector<double>& cdf) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::map<int, float> m;
  for (int k = 0; k < 4000; ++k) {
    const int w = static_cast<int>(std::lower_bound(cdf.begin(), cdf.end(), u(rng)) - cdf.begin());
    m[w] += 1.0f;
  }
  baselines::BowVector v(m.begin(), m.end());
  for (auto& e : v) e.second /= 4000.0f;
  return v;
}

void BM_BowQuery5000(benchmark::State& state) {
  const int words = 1000000;
  std::vector<double> cdf(words);
  double total = 0;
  for (int i = 0; i < words; ++i) cdf[i] = (total += 1.0 / (i + 10.0));
  for (double& c : cdf) c /= total;
  std::mt19937 rng(1);
  baselines::InvertedIndex index(words);
  for (int i = 0; i < 5000; ++i) index.add(zipf_bow(rng, cdf));
  std::vector<baselines::BowVector> queries;
  for (int i = 0; i < 16; ++i) queries.push_back(zipf_bow(rng, cdf));
  std::size_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(index.query(queries[i++ % 16], 1));
  state.counters["query_words"] = static_cast<double>(queries[0].size());
}
BENCHMARK(BM_BowQuery5000)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
