// Milliseconds per keyframe for each stage of the method, and per query for the exact
// difference-matrix row, on the k06-summer fixture (880 places). Single thread.
//   build/bench/loopscan_bench [--benchmark_filter=...]
// Each benchmark reports `per_item` = seconds per keyframe (or per query).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "loopscan/core/database/database.hpp"
#include "loopscan/core/descriptors/describe.hpp"
#include "loopscan/core/keyframe_stream.hpp"
#include "loopscan/core/matching/birds_eye_match.hpp"
#include "loopscan/core/matching/place_matcher.hpp"
#include "loopscan/core/pipeline/recognizer.hpp"
#include "loopscan/core/scan/camera_points.hpp"
#include "loopscan/core/scan/scan_imitator.hpp"
#include "loopscan/io/incoming_ids.hpp"
#include "loopscan/io/matrix_text.hpp"
#include "loopscan/io/sodso.hpp"

namespace loopscan {
namespace {

std::string fixture_dir() {
  const char* env = std::getenv("LOOPSCAN_SHARED");
  return std::string(env ? env : LOOPSCAN_SHARED_DIR) + "/fixtures/k06-summer";
}

struct Data {
  std::vector<KeyframePose> poses;
  std::vector<IdPoint> points;
  std::vector<Cloud> in_range;  // every 8th described keyframe
  std::vector<Cloud> cartesian, polar;
};

const Data& data() {
  static const Data d = [] {
    Data x;
    x.poses = io::read_sodso_poses(fixture_dir() + "/poses_history_file.txt");
    x.points = io::read_sodso_points(fixture_dir() + "/pts_history_file.txt.gz");
    ScanImitator im;
    Cloud in;
    int described = 0;
    for_each_keyframe(
        x.poses, x.points, [&](const KeyframePose& k, const IdPoint* p, std::size_t n) {
          if (im.add_keyframe(k, p, n, false, in) && described++ % 8 == 0) {
            x.in_range.push_back(in);
            x.cartesian.push_back(filter_scan(in, ScanFilter::Cartesian, ImitationConfig{}));
            x.polar.push_back(filter_scan(in, ScanFilter::Polar, ImitationConfig{}));
          }
        });
    return x;
  }();
  return d;
}

void per_item(benchmark::State& state, std::size_t items_per_iteration) {
  state.counters["per_item"] = benchmark::Counter(
      static_cast<double>(items_per_iteration) * static_cast<double>(state.iterations()),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// Local-map update + range crop over the whole sequence.
void BM_ImitateCrop(benchmark::State& state) {
  const Data& d = data();
  ImitationConfig cfg;
  cfg.mode = static_cast<Mode>(state.range(0));
  std::size_t scans = 0;
  for (auto _ : state) {
    ScanImitator im(cfg);
    Cloud in;
    scans = 0;
    for_each_keyframe(d.poses, d.points,
                      [&](const KeyframePose& k, const IdPoint* p, std::size_t n) {
                        scans += im.add_keyframe(k, p, n, false, in);
                        benchmark::DoNotOptimize(in.data());
                      });
  }
  per_item(state, scans);
}

// Default mode as `describe` runs it: crop to float SoA + vectorised filter, whole sequence.
void BM_ImitateFast(benchmark::State& state) {
  const Data& d = data();
  const auto filter = static_cast<ScanFilter>(state.range(0));
  std::size_t scans = 0, points = 0;
  for (auto _ : state) {
    ScanImitator im;
    CameraPoints in;
    scans = points = 0;
    for_each_keyframe(
        d.poses, d.points, [&](const KeyframePose& k, const IdPoint* p, std::size_t n) {
          if (im.add_keyframe(k, p, n, false, in)) {
            ++scans;
            points += in.size();
            benchmark::DoNotOptimize(filter_camera_points(in, filter, ImitationConfig{}).data());
          }
        });
  }
  per_item(state, scans);
  state.counters["points"] = static_cast<double>(points) / static_cast<double>(scans);  // cropped
}

void BM_Filter(benchmark::State& state) {
  const Data& d = data();
  ImitationConfig cfg;
  cfg.mode = static_cast<Mode>(state.range(0));
  const auto filter = static_cast<ScanFilter>(state.range(1));
  for (auto _ : state) {
    for (const Cloud& c : d.in_range) benchmark::DoNotOptimize(filter_scan(c, filter, cfg).data());
  }
  per_item(state, d.in_range.size());
}

void BM_Describe(benchmark::State& state) {
  const Data& d = data();
  const auto method = static_cast<Method>(state.range(0));
  const auto mode = static_cast<Mode>(state.range(1));
  const DescriptorConfig cfg = DescriptorConfig::for_mode(mode);
  const std::vector<Cloud>& scans = method == Method::ScanContext ? d.cartesian : d.polar;
  // Reference M2DP (8 Jacobi SVDs per keyframe) is slow: time a subset.
  const std::size_t n = method == Method::M2dp && mode == Mode::Reference ? 8 : scans.size();
  for (auto _ : state) {
    for (std::size_t i = 0; i < n; ++i)
      benchmark::DoNotOptimize(describe(method, scans[i], cfg).data());
  }
  per_item(state, n);
  std::size_t points = 0;
  for (std::size_t i = 0; i < n; ++i) points += scans[i].size();
  state.counters["points"] = static_cast<double>(points) / static_cast<double>(n);  // a scan
}

// Times one difference-matrix row per iteration: `n` places (sigs cycled), queries cycling
// through sigs.
void time_rows(benchmark::State& state, Method method, Precision precision,
               const std::vector<Signature>& sigs, std::size_t n) {
  const auto matcher = make_matcher(method, precision);
  for (std::size_t i = 0; i < n; ++i) matcher->add(sigs[i % sigs.size()]);
  Eigen::MatrixXd rows;
  std::size_t q = 0;
  for (auto _ : state) {
    matcher->distances(sigs[q++ % sigs.size()], rows);
    benchmark::DoNotOptimize(rows.data());
  }
  per_item(state, 1);
}

// One exact difference-matrix row (all components) against the 880 reference places.
void BM_Query(benchmark::State& state) {
  const auto method = static_cast<Method>(state.range(0));
  const auto precision = static_cast<Precision>(state.range(1));
  static std::vector<Signature> places[3];
  std::vector<Signature>& sigs = places[state.range(0)];
  if (sigs.empty()) {
    const Eigen::MatrixXd all = io::read_matrix_text(fixture_dir() + "/reference/signatures_" +
                                                     method_name(method) + ".txt.gz");
    const int rows = rows_per_place(method);
    for (Eigen::Index i = 0; i + rows <= all.rows(); i += rows)
      sigs.push_back(all.middleRows(i, rows));
  }
  const std::size_t n = state.range(2) > 0 ? std::size_t(state.range(2)) : sigs.size();
  time_rows(state, method, precision, sigs, n);
  state.counters["places"] = static_cast<double>(n);
}

// Default-mode Scan Context: a query with its 4 lateral versions against 880 places (the
// fixture's 110 described keyframes, cycled), each place's own row only, as the matchers do.
void BM_QueryScanContextVersions(benchmark::State& state) {
  const Data& d = data();
  const DescriptorConfig cfg = DescriptorConfig::for_mode(Mode::Default);
  std::vector<Signature> sigs;
  for (const Cloud& c : d.cartesian) sigs.push_back(describe(Method::ScanContext, c, cfg));
  time_rows(state, Method::ScanContext, Precision::Float, sigs, 880);
  state.counters["query_rows"] = static_cast<double>(sigs.front().rows());
}

// The streaming Recognizer (default Scan Context: imitate, describe, query, add) over every
// fixture keyframe; the Python binding's benchmark (bench/python) times the same calls.
void BM_RecognizerStream(benchmark::State& state) {
  const Data& d = data();
  for (auto _ : state) {
    Recognizer r(RecognizerConfig::make(Method::ScanContext));
    for_each_keyframe(d.poses, d.points,
                      [&](const KeyframePose& k, const IdPoint* p, std::size_t n) {
                        benchmark::DoNotOptimize(r.add_keyframe(k, p, n).size());
                      });
  }
  per_item(state, d.poses.size());
}

// The bird's-eye place (docs/experiments/birds-eye-place.md) on the in-range points.
const std::vector<BirdsEyePlace>& birds_eye_places() {
  static const std::vector<BirdsEyePlace> places = [] {
    std::vector<BirdsEyePlace> out;
    const BirdsEyeDescriber describer;
    for (const Cloud& c : data().polar) {  // the scans the pipeline describes
      const CameraPoints p = to_camera_points(c);
      out.push_back(describer.describe(p.x.data(), p.y.data(), p.z.data(), p.size()));
    }
    return out;
  }();
  return places;
}

void BM_BirdsEyeDescribe(benchmark::State& state) {
  const Data& d = data();
  std::vector<CameraPoints> scans;
  for (const Cloud& c : d.polar) scans.push_back(to_camera_points(c));  // as the pipeline
  const BirdsEyeDescriber describer;
  for (auto _ : state) {
    for (const CameraPoints& p : scans) {
      benchmark::DoNotOptimize(describer.describe(p.x.data(), p.y.data(), p.z.data(), p.size()).key.data());
    }
  }
  per_item(state, scans.size());
}

// One query's keys against 880 places (the described keyframes cycled), through the spectra.
void BM_BirdsEyeKeyRow(benchmark::State& state) {
  const BirdsEyePlaceConfig config;
  std::vector<BirdsEyeKeySpectrum> keys;
  for (const BirdsEyePlace& p : birds_eye_places()) keys.push_back(key_spectrum(p, config.angles));
  std::size_t q = 0;
  for (auto _ : state) {
    const BirdsEyeKeySpectrum& query = keys[q++ % keys.size()];
    double best = 2;
    for (std::size_t j = 0; j < 880; ++j) best = std::min(best, match_key_spectra(query, keys[j % keys.size()]).distance);
    benchmark::DoNotOptimize(best);
  }
  per_item(state, 1);
}

// The image search of one finalist (the key's yaw and the yaw plus pi, +-12 m): every shift
// at full resolution (coarse 1), or coarse to fine around the best peaks.
void BM_BirdsEyePose(benchmark::State& state) {
  const BirdsEyePlaceConfig config;
  BirdsEyeSearchConfig search;
  search.coarse_cells = static_cast<int>(state.range(0));
  search.refined_peaks = static_cast<int>(state.range(1));
  const auto& places = birds_eye_places();
  std::vector<double> yaws;  // each place against the next: the key's yaw, outside the timing
  for (std::size_t i = 0; i < places.size(); ++i) {
    yaws.push_back(match_keys(places[i], places[(i + 1) % places.size()], config.angles).yaw_rad);
  }
  std::size_t q = 0;
  for (auto _ : state) {
    const std::size_t i = q++ % places.size();
    benchmark::DoNotOptimize(
        birds_eye_pose(places[i], places[(i + 1) % places.size()], yaws[i], config, search).score);
  }
  per_item(state, 1);
}

// A database query as `db query` and the Recognizer run it: every place's key, then the image
// search of the finalists, against 880 places (the described keyframes cycled).
void BM_BirdsEyeQuery(benchmark::State& state) {
  DatabaseConfig config;
  config.method = Method::BirdsEye;
  config.birds_eye_search.finalists = static_cast<int>(state.range(0));
  Database db(config);
  const auto& places = birds_eye_places();
  for (int i = 0; i < 880; ++i) {
    db.add({0, i}, {birds_eye_signature(places[static_cast<std::size_t>(i) % places.size()])});
  }
  QueryOptions options;
  options.retrieval = Retrieval::Exact;
  std::size_t q = 0;
  for (auto _ : state) {
    const BirdsEyePlace& query = places[q++ % places.size()];
    benchmark::DoNotOptimize(db.query({birds_eye_signature(query)}, 1, options).size());
  }
  per_item(state, 1);
}

constexpr int kRef = static_cast<int>(Mode::Reference), kDef = static_cast<int>(Mode::Default);
constexpr int kCart = static_cast<int>(ScanFilter::Cartesian),
              kPol = static_cast<int>(ScanFilter::Polar);
constexpr int kSc = 0, kM2dp = 1, kDelight = 2;
constexpr int kFloat = static_cast<int>(Precision::Float),
              kDouble = static_cast<int>(Precision::Double);

BENCHMARK(BM_ImitateCrop)
    ->ArgNames({"mode"})
    ->Args({kRef})
    ->Args({kDef})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);
BENCHMARK(BM_ImitateFast)
    ->ArgNames({"filter"})
    ->Args({kCart})
    ->Args({kPol})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);
BENCHMARK(BM_Filter)
    ->ArgNames({"mode", "filter"})
    ->Args({kRef, kCart})
    ->Args({kDef, kCart})
    ->Args({kRef, kPol})
    ->Args({kDef, kPol})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Describe)
    ->ArgNames({"method", "mode"})
    ->Args({kSc, kRef})
    ->Args({kSc, kDef})
    ->Args({kM2dp, kRef})
    ->Args({kM2dp, kDef})
    ->Args({kDelight, kRef})
    ->Args({kDelight, kDef})
    ->Unit(benchmark::kMillisecond);
// places = 0: the 880 fixture places; otherwise that many (cycled), to see cache effects.
BENCHMARK(BM_Query)
    ->ArgNames({"method", "double", "places"})
    ->Args({kSc, kFloat, 0})
    ->Args({kSc, kDouble, 0})
    ->Args({kM2dp, kFloat, 0})
    ->Args({kM2dp, kDouble, 0})
    ->Args({kDelight, kFloat, 0})
    ->Args({kDelight, kDouble, 0})
    ->Args({kSc, kFloat, 96})
    ->Args({kM2dp, kFloat, 96})
    ->Args({kDelight, kFloat, 96})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_QueryScanContextVersions)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RecognizerStream)->Unit(benchmark::kMillisecond)->Iterations(2);
BENCHMARK(BM_BirdsEyeDescribe)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BirdsEyeKeyRow)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BirdsEyeQuery)->ArgNames({"finalists"})->Arg(10)->Arg(5)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_BirdsEyePose)
    ->ArgNames({"coarse", "peaks"})
    ->Args({1, 1})
    ->Args({2, 3})
    ->Args({2, 5})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace loopscan

int main(int argc, char** argv) {
  if (!std::filesystem::exists(loopscan::fixture_dir() + "/poses_history_file.txt")) {
    std::fprintf(stderr, "loopscan_bench: fixture not found at %s (set LOOPSCAN_SHARED)\n",
                 loopscan::fixture_dir().c_str());
    return 0;
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
