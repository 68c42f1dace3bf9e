// loopscan db build: described sequences (one session each) -> a place database file.
// loopscan db query: a database + a described sequence -> candidates.csv (+ metrics with GT).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <Eigen/Geometry>

#include <nlohmann/json.hpp>

#include "commands.hpp"
#include "evaluation_outputs.hpp"
#include "loopscan/core/database/database.hpp"
#include "loopscan/core/database/lane_query.hpp"
#include "loopscan/eval/precision_recall.hpp"
#include "loopscan/io/atomic_file.hpp"
#include "loopscan/io/database_file.hpp"
#include "loopscan/io/errors.hpp"
#include "loopscan/io/signature_set.hpp"
#include "options.hpp"
#include "output_sets.hpp"
#include "progress.hpp"

namespace loopscan::cli {
namespace {

struct BuildArgs {
  std::string method = "sc", fusion = "fused", gt_format = "kitti", storage = "full", out;
  std::vector<std::string> signatures, gt;
  int first_session = 0;
};

struct QueryArgs {
  std::string db, signatures, gt, gt_format = "kitti", out;
  std::vector<std::string> lanes;  // describe outputs of the same places from the next lanes
  int k = 5, candidates = 50, exclude_recent = 0, mask = 0;
  std::vector<int> sessions;
  double uniqueness = 1.0, max_distance = -1, threshold_m = 25.0;
  bool exact = false;
};

// Ground truth travels with the place as a world-to-camera pose at its position whose camera z
// axis (forward) is the ground-truth heading (identity rotation when the heading is unknown).
Pose3x4 position_pose(const Eigen::Vector3d& p, const Eigen::Vector3d& heading) {
  Eigen::Matrix3d R_world_cam = Eigen::Matrix3d::Identity();
  if (heading.norm() > 0.5) {
    const Eigen::Vector3d z = heading.normalized();
    Eigen::Vector3d x = z.unitOrthogonal();
    if (std::abs(z.y()) < 0.9) x = Eigen::Vector3d::UnitY().cross(z).normalized();
    R_world_cam << x, z.cross(x), z;
  }
  Pose3x4 T;
  T.leftCols<3>() = R_world_cam.transpose();
  T.col(3) = -R_world_cam.transpose() * p;
  return T;
}

void run_build(const BuildArgs& a) {
  if (!a.gt.empty() && a.gt.size() != a.signatures.size()) {
    throw std::invalid_argument("give one --gt per --signatures (or none)");
  }
  DatabaseConfig config;
  config.method = parse_method(a.method);
  config.fusion = parse_fusion(a.fusion);
  config.storage = a.storage == "compact" ? PlaceStorage::Compact : PlaceStorage::Full;
  Database db(config);
  for (std::size_t s = 0; s < a.signatures.size(); ++s) {
    io::SignatureSet set = io::load_signature_set(a.signatures[s], config.method);
    if (!a.gt.empty()) io::attach_positions(set, a.gt[s], a.gt_format);
    const int session = a.first_session + static_cast<int>(s);
    StepProgress progress("db build: session " + std::to_string(session), "places");
    for (std::size_t i = 0; i < set.places.size(); ++i) {
      std::optional<Pose3x4> pose;
      if (!set.positions.empty()) pose = position_pose(set.positions[i], set.headings[i]);
      try {
        db.add({session, set.keyframe_ids[i]}, {set.places[i], set.frames[i]}, pose);
      } catch (const std::invalid_argument& e) {
        throw io::InputError(a.signatures[s], 0, e.what());
      }
      progress.update(i + 1, set.places.size());
    }
    progress.finish();
    std::printf("session %d: %zu places from %s\n", session, set.places.size(),
                a.signatures[s].c_str());
  }
  io::save_database(db, a.out);
  std::printf("%s database: %zu places, %.1f KB per place in memory -> %s\n",
              method_name(config.method).c_str(), db.size(),
              db.size() ? double(db.memory_bytes()) / double(db.size()) / 1000.0 : 0.0,
              shown(a.out).c_str());
}

void run_query(const QueryArgs& a) {
  const Database db = io::load_database(a.db);
  io::SignatureSet queries = io::load_signature_set(a.signatures, db.config().method);
  const bool with_gt = !a.gt.empty();
  if (with_gt) io::attach_positions(queries, a.gt, a.gt_format);
  std::vector<io::SignatureSet> lanes;
  for (const std::string& dir : a.lanes) {
    lanes.push_back(io::load_signature_set(dir, db.config().method));
    if (lanes.back().keyframe_ids != queries.keyframe_ids) {
      throw io::InputError(dir, 0,
                           "the keyframe ids of --signatures " + a.signatures +
                               " (a lane version describes the same places)");
    }
  }

  QueryOptions options;
  options.retrieval = a.exact ? Retrieval::Exact : Retrieval::Indexed;
  options.candidates = a.candidates;
  options.exclude_recent = a.exclude_recent;
  options.sessions = a.sessions;
  options.uniqueness_ratio = a.uniqueness;
  if (a.max_distance >= 0) options.max_distance = a.max_distance;

  std::ostringstream csv;
  csv.precision(10);
  csv << "query_id,rank,session,keyframe,distance,yaw_deg,mirrored\n";
  std::vector<eval::QueryMatch> matches;
  double total_ms = 0;
  StepProgress progress("db query", "queries");
  for (std::size_t i = 0; i < queries.places.size(); ++i) {
    if (a.mask > 0) {  // the database holds this very sequence: skip its neighbours
      options.accept = outside_band(i, static_cast<std::size_t>(a.mask));
    }
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<Candidate> found;
    try {
      std::vector<PlaceDescriptor> versions;
      for (const io::SignatureSet& lane : lanes)
        versions.push_back({lane.places[i], lane.frames[i]});
      found = query_with_lane_versions(db, {queries.places[i], queries.frames[i]}, versions, a.k,
                                       options);
    } catch (const std::invalid_argument& e) {
      throw io::InputError(a.signatures, 0, e.what());
    }
    total_ms +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    for (std::size_t r = 0; r < found.size(); ++r) {
      const Candidate& c = found[r];
      csv << queries.keyframe_ids[i] << ',' << r + 1 << ',' << c.place.session << ','
          << c.place.keyframe << ',' << c.distance << ',' << c.yaw_rad * 180.0 / M_PI << ','
          << (c.mirrored ? 1 : 0) << '\n';
    }
    const int q = static_cast<int>(i);
    matches.push_back(
        found.empty() ? eval::QueryMatch{q, -1, std::numeric_limits<double>::infinity()}
                      : eval::QueryMatch{q, static_cast<int>(found[0].index), found[0].distance});
    progress.update(i + 1, queries.places.size());
  }
  progress.finish();
  std::filesystem::create_directories(a.out);
  io::write_file_atomic(a.out + "/candidates.csv", csv.str());
  const double query_ms = queries.places.empty() ? 0.0 : total_ms / queries.places.size();
  std::printf("%zu queries against %zu places: %.3f ms per query (%s) -> %s/candidates.csv\n",
              queries.places.size(), db.size(), query_ms, a.exact ? "exact" : "indexed",
              shown(a.out).c_str());
  if (!with_gt) return;

  // Database positions: from the poses `db build --gt` stored.
  std::vector<Eigen::Vector3d> db_pos(db.size()), db_headings(db.size());
  std::vector<int> db_ids(db.size());
  for (std::size_t j = 0; j < db.size(); ++j) {
    const std::optional<Pose3x4> T = db.pose(j);
    if (!T) {
      throw io::InputError(a.db, 0,
                           "a pose for every place to evaluate against (build the "
                           "database with --gt); place " +
                               std::to_string(j) + " has none");
    }
    db_pos[j] = -T->leftCols<3>().transpose() * T->col(3);
    db_headings[j] = T->leftCols<3>().row(2).transpose();  // the camera z axis in the world
    db_ids[j] = db.place(j).keyframe;
  }
  eval::Protocol protocol{a.threshold_m, a.mask};
  const eval::PrResult pr = eval::evaluate_matches(matches, queries.positions, db_pos, protocol);
  nlohmann::json metrics = {
      {"method", method_name(db.config().method)},
      {"fusion", fusion_name(db.config().fusion)},
      {"storage", db.config().storage == PlaceStorage::Compact ? "compact" : "full"},
      {"retrieval", a.exact ? "exact" : "indexed"},
      {"candidates", a.candidates},
      {"protocol", {{"threshold_m", protocol.threshold_m}, {"mask_width", protocol.mask_width}}},
      {"n_database", db.size()},
      {"query_ms", query_ms}};
  metrics.update(pr_metrics(pr));
  metrics["by_direction"] = direction_metrics(eval::split_by_direction(
      pr, queries.positions, db_pos, queries.headings, db_headings, protocol));
  const std::string title =
      method_name(db.config().method) + " database (" + (a.exact ? "exact" : "indexed") + ")";
  write_evaluation(a.out, queries.keyframe_ids, db_ids, pr, metrics, title);
  std::printf("%s: AUC %.4f, recall@100%%P %.4f, F1-max %.4f, %d GT loops\n", title.c_str(), pr.auc,
              pr.recall_at_100_precision, pr.f1_max, pr.n_gt_loops);
}

}  // namespace

void add_db_command(CLI::App& app) {
  CLI::App* db = app.add_subcommand("db", "Build and query a place database (online retrieval)");
  db->require_subcommand(1);

  auto b = std::make_shared<BuildArgs>();
  CLI::App* build = db->add_subcommand("build", "Described sequences -> database file");
  build->add_option("--method", b->method, "sc | m2dp | delight")->capture_default_str();
  build
      ->add_option("--signatures", b->signatures,
                   "describe output dir; repeat for more sessions (numbered in order)")
      ->required();
  build->add_option("--gt", b->gt, "ground truth per --signatures (stored as place positions)");
  build->add_option("--gt-format", b->gt_format, "kitti | robotcar")->capture_default_str();
  build->add_option("--fusion", b->fusion, "fused | structure | intensity")->capture_default_str();
  build
      ->add_option("--storage", b->storage,
                   "full | compact (Scan Context: a byte per spectrum value, ~3.4x smaller)")
      ->check(CLI::IsMember({"full", "compact"}))
      ->capture_default_str();
  build->add_option("--first-session", b->first_session, "session id of the first --signatures")
      ->check(finite_in(0, 1e6))
      ->capture_default_str();
  build->add_option("--out", b->out, "database file")->required();
  build->callback([b] {
    BuildArgs args = *b;
    const auto is_database = [](const std::string& p) { return starts_with_bytes(p, "LOOPSCDB"); };
    with_output_file(args.out, is_database, [&] { run_build(args); });
  });

  auto q = std::make_shared<QueryArgs>();
  CLI::App* query = db->add_subcommand("query", "Query a database with a described sequence");
  query->add_option("--db", q->db, "database file (db build)")->required();
  query->add_option("--lanes", q->lanes,
                    "describe outputs of the same places from the next lanes (sc, --frame camera "
                    "--lateral-offset -3.5 / 3.5): they match reverse drives only");
  query->add_option("--signatures", q->signatures, "describe output dir of the queries")
      ->required();
  query->add_option("--k", q->k, "results per query")
      ->check(finite_in(1, 10000))
      ->capture_default_str();
  query->add_flag("--exact", q->exact, "exact search instead of the index");
  query->add_option("--candidates", q->candidates, "index candidates scored exactly")
      ->check(finite_in(1, 1e6))
      ->capture_default_str();
  query->add_option("--sessions", q->sessions, "only places of these sessions")
      ->check(finite_in(0, 1e6));
  query->add_option("--exclude-recent", q->exclude_recent, "ignore the N places added last")
      ->check(finite_in(0, kMaxCount));
  query->add_option("--uniqueness", q->uniqueness, "uniqueness ratio (1: off)")
      ->check(finite_in(0, 1))
      ->capture_default_str();
  query->add_option("--max-distance", q->max_distance, "drop results farther than this")
      ->check(finite_in(-1e12, 1e12));
  query->add_option("--gt", q->gt, "ground truth of the queries: adds metrics, PR curve");
  query->add_option("--gt-format", q->gt_format, "kitti | robotcar")->capture_default_str();
  query->add_option("--threshold", q->threshold_m, "loop distance in m")
      ->check(finite_in(1e-3, 1e6))
      ->capture_default_str();
  query
      ->add_option("--mask", q->mask,
                   "the database holds these very places: skip |i - j| < mask (100 like "
                   "evaluate's same-session protocol)")
      ->check(finite_in(0, kMaxCount))
      ->capture_default_str();
  query->add_option("--out", q->out, "output directory")->required();
  run_writing_dir(query, q, run_query);
}

}  // namespace loopscan::cli
