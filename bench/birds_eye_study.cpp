// Study of the bird's-eye place (docs/experiments/birds-eye-place.md): imitates every keyframe's
// scan of a VO sequence (as `describe` and the Recognizer do), describes it with
// density cells and with height cells, and evaluates recognition by the paper's protocol: each
// query's best place by key distance alone, and after the image search on the key's K best
// (finalists); then with the cell kind whose keys separate better over the whole run. Same
// session (10 m, mask 100), or a query session against a map session (25 m, no mask).
//
//   loopscan_birds_eye_study MAP_DIR [QUERY_DIR] [--finalists K] [--in-range]
//                            [--window START END] [--pose-window START END] [--range R]
//                            [--significance] [--sequence L]...
//
// K, the weight windows of the images and of the pose search (m), and the image's range R
// (m): the library defaults. --significance adds a row per cell kind: the image search's best
// places ranked by how far their correlation peak stands out of its surface (peak to sidelobe)
// instead of by its score. Places are described from the scan `describe` and the Recognizer
// describe (polar-filtered); --in-range describes every in-range point instead. --sequence L
// adds a row per cell kind that ranks each query's finalists by their mean image distance along
// the last L queries (see sequence_matches).
//
// Each directory holds poses_history_file.txt, pts_history_file.txt[.gz] and gt.txt.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "loopscan/core/keyframe_stream.hpp"
#include "loopscan/core/matching/birds_eye_match.hpp"
#include "loopscan/core/scan/camera_points.hpp"
#include "loopscan/core/parallel.hpp"
#include "loopscan/core/pipeline/describe_sequence.hpp"
#include "loopscan/core/timing.hpp"
#include "loopscan/eval/direction_split.hpp"
#include "loopscan/io/ground_truth_files.hpp"
#include "loopscan/io/sodso.hpp"

using namespace loopscan;

namespace {

constexpr int kDensity = 0, kHeight = 1;
const char* const kCellNames[] = {"density", "height"};

struct Session {
  std::array<std::vector<BirdsEyePlace>, 2> places;  // per cell kind
  std::array<std::vector<BirdsEyeKeySpectrum>, 2> keys;
  std::vector<Eigen::Vector3d> positions, headings;
  double imitate_ms = 0;
  std::array<double, 2> describe_ms{};
};

std::string points_file(const std::string& dir) {
  const std::string plain = dir + "/pts_history_file.txt";
  return std::filesystem::exists(plain) ? plain : plain + ".gz";
}

// pipeline_scan: the scan `describe` and the Recognizer describe (the bird's-eye method's
// filter); otherwise every in-range point.
Session load(const std::string& dir, const std::array<BirdsEyePlaceConfig, 2>& configs,
             bool pipeline_scan) {
  const auto poses = io::read_sodso_poses(dir + "/poses_history_file.txt");
  const auto points = io::read_sodso_points(points_file(dir));
  const auto format = io::detect_gt_format(dir + "/gt.txt");
  const auto positions = io::read_positions(dir + "/gt.txt", format);
  const auto headings = io::read_headings(dir + "/gt.txt", format);
  const auto options = SequenceOptions::make(Method::ScanContext, Mode::Default);
  const std::vector<int> resets = detect_vo_resets(poses);
  ScanImitator imitator(options.imitation);
  const std::array<BirdsEyeDescriber, 2> describers{BirdsEyeDescriber(configs[0]),
                                                    BirdsEyeDescriber(configs[1])};
  const ScanFilter filter = filter_for(pipeline_scan ? Method::BirdsEye : Method::ScanContext);
  Session s;
  std::vector<ReadyScan> ready;
  auto take = [&] {
    for (const ReadyScan& r : ready) {
      const CameraPoints scan = pipeline_scan ? to_camera_points(r.scan) : r.in_range;
      for (int c : {kDensity, kHeight}) {
        const auto t0 = std::chrono::steady_clock::now();
        s.places[c].push_back(
            describers[c].describe(scan.x.data(), scan.y.data(), scan.z.data(), scan.size()));
        s.keys[c].push_back(key_spectrum(s.places[c].back(), configs[c].angles));
        s.describe_ms[c] += ms_since(t0);
      }
      if (std::size_t(r.keyframe.id) >= positions.size()) {
        throw std::runtime_error(dir + "/gt.txt: no row for keyframe " +
                                 std::to_string(r.keyframe.id));
      }
      s.positions.push_back(positions[r.keyframe.id]);
      s.headings.push_back(headings[r.keyframe.id]);
    }
    ready.clear();
  };
  for_each_keyframe(poses, points, [&](const KeyframePose& k, const IdPoint* first, std::size_t n) {
    const bool reset = std::find(resets.begin(), resets.end(), k.id) != resets.end();
    const auto t0 = std::chrono::steady_clock::now();
    imitator.push(k, first, n, reset, filter, ready);
    s.imitate_ms += ms_since(t0);
    take();
  });
  imitator.finish(filter, ready);
  take();
  const double n = std::max<double>(1, s.positions.size());
  s.imitate_ms /= n;
  for (double& ms : s.describe_ms) ms /= n;
  return s;
}

void report(const std::string& what, const std::vector<eval::QueryMatch>& matches,
            const Session& q, const Session& db, const eval::Protocol& protocol) {
  const auto pr = eval::evaluate_matches(matches, q.positions, db.positions, protocol);
  const auto split = eval::split_by_direction(pr, q.positions, db.positions, q.headings,
                                              db.headings, protocol);
  std::printf("| %s | %.3f | %.3f | %d/%d | %d/%d |\n", what.c_str(), pr.auc,
              pr.recall_at_100_precision, split.same.top1_correct, split.same.n_loops,
              split.opposite.top1_correct, split.opposite.n_loops);
}

// How far a query's best key stands out of its row: (median - best) / (median - 10th
// percentile). Sorts `row`.
double separation(std::vector<float>& row) {
  std::sort(row.begin(), row.end());
  const double median = row[row.size() / 2], tenth = row[row.size() / 10];
  return (median - row[0]) / std::max(1e-9, median - tenth);
}

// How far a correlation peak stands out of the rest of its surface (peak to sidelobe): (peak -
// mean) / deviation of the shifts more than `guard` cells from the peak.
double peak_to_sidelobe(const std::vector<double>& surface, int side, int guard) {
  int top = 0;
  for (int i = 1; i < int(surface.size()); ++i) {
    if (surface[i] > surface[top]) top = i;
  }
  double sum = 0, sum2 = 0;
  int n = 0;
  for (int i = 0; i < int(surface.size()); ++i) {
    if (std::abs(i / side - top / side) <= guard && std::abs(i % side - top % side) <= guard)
      continue;
    if (!std::isfinite(surface[i])) continue;
    sum += surface[i];
    sum2 += surface[i] * surface[i];
    ++n;
  }
  if (n < 2) return 0;
  const double mean = sum / n, deviation = std::sqrt(std::max(1e-12, sum2 / n - mean * mean));
  return (surface[top] - mean) / deviation;
}

struct CellResult {
  std::vector<eval::QueryMatch> by_key, by_image;
  std::vector<eval::QueryMatch> by_significance;  // by_image's place, ranked by peak to sidelobe
  std::vector<std::vector<std::pair<int, double>>> finalists;  // per query: (place, image distance)
  double separation = 0;  // mean over queries
  double key_us = 0, image_ms = 0;
};

CellResult evaluate_cells(int cell, const Session& queries, const Session& db, bool cross,
                          const eval::Protocol& protocol, const BirdsEyePlaceConfig& config,
                          const BirdsEyeSearchConfig& search, bool significance) {
  const int finalists = search.finalists;
  const int nq = int(queries.positions.size()), nd = int(db.positions.size());
  CellResult out;
  out.by_key.assign(nq, {0, 0, std::numeric_limits<double>::infinity()});
  for (int i = 0; i < nq; ++i) out.by_key[i].query = i;
  out.by_image = out.by_key;
  out.by_significance = out.by_key;
  out.finalists.assign(nq, {});
  std::array<double, 2> key_ms{}, image_ms{}, separations{};
  std::array<long, 2> pairs{}, searched{};
  run_on_threads(2, [&](int t) {
    std::vector<std::pair<double, int>> keyed;
    std::vector<float> row;
    std::vector<double> yaw(nd, 0);
    for (int i = t; i < nq; i += 2) {
      keyed.clear();
      row.clear();
      auto t0 = std::chrono::steady_clock::now();
      for (int j = 0; j < nd; ++j) {
        if (!cross && std::abs(i - j) < protocol.mask_width) continue;
        const BirdsEyeKeyMatch m = match_key_spectra(queries.keys[cell][i], db.keys[cell][j]);
        keyed.push_back({m.distance, j});
        row.push_back(float(m.distance));
        yaw[j] = m.yaw_rad;
      }
      key_ms[t] += ms_since(t0);
      pairs[t] += long(keyed.size());
      if (keyed.empty()) continue;
      if (row.size() >= 20) separations[t] += separation(row);
      double best_yaw = 0;
      const int k = std::min<int>(finalists, int(keyed.size()));
      std::partial_sort(keyed.begin(), keyed.begin() + k, keyed.end());
      out.by_key[i] = {i, keyed[0].second, keyed[0].first};
      t0 = std::chrono::steady_clock::now();
      for (int f = 0; f < k; ++f) {
        const int j = keyed[f].second;
        const BirdsEyePose pose =
            birds_eye_pose(queries.places[cell][i], db.places[cell][j], yaw[j], config, search);
        out.finalists[i].push_back({j, 1.0 - pose.score});
        if (1.0 - pose.score < out.by_image[i].distance) {
          out.by_image[i] = {i, j, 1.0 - pose.score};
          best_yaw = pose.yaw_rad;
        }
        ++searched[t];
      }
      image_ms[t] += ms_since(t0);
      if (significance && out.by_image[i].distance < 1.0) {
        const int m = int(search.max_shift_m / config.cell_m);
        const double psr = peak_to_sidelobe(
            birds_eye_correlation(queries.places[cell][i], db.places[cell][out.by_image[i].match],
                                  best_yaw, config, m),
            2 * m + 1, 2);
        out.by_significance[i] = {i, out.by_image[i].match, 1.0 / (1.0 + std::max(0.0, psr))};
      }
    }
  });
  out.separation = (separations[0] + separations[1]) / std::max(1, nq);
  out.key_us = 1000 * (key_ms[0] + key_ms[1]) / std::max(1.0, double(pairs[0] + pairs[1]));
  out.image_ms = (image_ms[0] + image_ms[1]) / std::max(1.0, double(searched[0] + searched[1]));
  return out;
}

// Each query's finalists ranked by the mean image distance along the last `length` queries: a
// query k back counts the smallest distance among its finalists within 2.5 k + 3 places of the
// candidate (either direction of travel), or 1 if none is.
std::vector<eval::QueryMatch> sequence_matches(
    const std::vector<std::vector<std::pair<int, double>>>& finalists, int length) {
  constexpr double kPlacesPerQuery = 2.5, kSlackPlaces = 3;
  const int nq = int(finalists.size());
  std::vector<eval::QueryMatch> out(nq);
  for (int i = 0; i < nq; ++i) {
    out[i] = {i, 0, std::numeric_limits<double>::infinity()};
    for (const auto& [j, d] : finalists[i]) {
      double sum = d;
      int n = 1;
      for (int k = 1; k < length && i - k >= 0; ++k, ++n) {
        double best = 1.0;
        for (const auto& [j2, d2] : finalists[i - k]) {
          if (std::abs(j2 - j) <= kPlacesPerQuery * k + kSlackPlaces) best = std::min(best, d2);
        }
        sum += best;
      }
      if (sum / n < out[i].distance) out[i] = {i, j, sum / n};
    }
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> dirs;
  BirdsEyeSearchConfig search;
  int& finalists = search.finalists;
  bool pipeline_scan = true, significance = false;
  std::vector<int> sequences;
  BirdsEyePlaceConfig layout;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--finalists" && i + 1 < argc) {
      finalists = std::atoi(argv[++i]);
    } else if (a == "--window" && i + 2 < argc) {
      layout.taper_start_m = std::atof(argv[++i]);
      layout.taper_end_m = std::atof(argv[++i]);
    } else if (a == "--pose-window" && i + 2 < argc) {
      search.pose_window_start_m = std::atof(argv[++i]);
      search.pose_window_end_m = std::atof(argv[++i]);
    } else if (a == "--range" && i + 1 < argc) {
      layout.range_m = std::atof(argv[++i]);
    } else if (a == "--significance") {
      significance = true;
    } else if (a == "--sequence" && i + 1 < argc) {
      sequences.push_back(std::atoi(argv[++i]));
    } else if (a == "--in-range") {
      pipeline_scan = false;
    } else {
      dirs.push_back(a);
    }
  }
  if (dirs.empty() || dirs.size() > 2 || finalists < 1) {
    std::fprintf(stderr,
                 "usage: loopscan_birds_eye_study MAP_DIR [QUERY_DIR] [--finalists K] "
                 "[--in-range] [--window START END] [--pose-window START END] [--range R] "
                 "[--significance] [--sequence L]...\n");
    return 2;
  }
  try {
    validate(layout);
    validate(search, layout);
    std::array<BirdsEyePlaceConfig, 2> configs{layout, layout};
    configs[kHeight].cell = BirdsEyeCell::Height;
    const bool cross = dirs.size() == 2;
    const Session db = load(dirs[0], configs, pipeline_scan);
    const Session q = cross ? load(dirs[1], configs, pipeline_scan) : Session{};
    const Session& queries = cross ? q : db;
    const eval::Protocol protocol =
        cross ? eval::cross_session_protocol() : eval::same_session_protocol();
    std::printf("| %s | AUC | R@100%%P | same-direction top-1 | opposite top-1 |\n",
                cross ? (dirs[0] + " map, " + dirs[1] + " queries").c_str() : dirs[0].c_str());
    std::printf("| --- | --- | --- | --- | --- |\n");
    std::array<CellResult, 2> results;
    const std::string image = ", image search on " + std::to_string(finalists) + " finalists";
    for (int c : {kDensity, kHeight}) {
      results[c] =
          evaluate_cells(c, queries, db, cross, protocol, configs[c], search, significance);
      report(std::string(kCellNames[c]) + " cells, key", results[c].by_key, queries, db, protocol);
      report(std::string(kCellNames[c]) + " cells" + image, results[c].by_image, queries, db,
             protocol);
      if (significance) {
        report(std::string(kCellNames[c]) + " cells" + image + ", ranked by peak to sidelobe",
               results[c].by_significance, queries, db, protocol);
      }
      for (int length : sequences) {
        report(std::string(kCellNames[c]) + " cells" + image + ", sequence of " +
                   std::to_string(length),
               sequence_matches(results[c].finalists, length), queries, db, protocol);
      }
    }
    const int chosen = results[kHeight].separation > results[kDensity].separation ? kHeight : kDensity;
    report("cells that separate better (" + std::string(kCellNames[chosen]) + ")" + image,
           results[chosen].by_image, queries, db, protocol);
    std::printf("\n%zu places, %zu bytes each. Key separation (mean (median - best) / (median - "
                "10th percentile) of a query's keys): density %.2f, height %.2f. One thread: "
                "imitate %.3f ms, describe %.3f ms (density) a place; key %.2f us a pair; image "
                "search %.3f ms a finalist.\n",
                db.positions.size(), db.places[0].empty() ? std::size_t(0) : db.places[0][0].bytes(),
                results[kDensity].separation, results[kHeight].separation, db.imitate_ms,
                db.describe_ms[kDensity], results[kDensity].key_us, results[kDensity].image_ms);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "loopscan_birds_eye_study: %s\n", e.what());
    return 1;
  }
  return 0;
}
