// loopscan db build: described sequences (one session each) -> a place database file.
// loopscan db query: a database + a described sequence -> candidates.csv (+ metrics with GT).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "cli/commands.hpp"
#include "cli/configuration.hpp"
#include "cli/options.hpp"
#include "cli/output_sets.hpp"
#include "cli/progress.hpp"
#include "loopscan/core/database/database.hpp"
#include "loopscan/core/database/lane_query.hpp"
#include "loopscan/eval/precision_recall.hpp"
#include "loopscan/io/atomic_file.hpp"
#include "loopscan/io/database_file.hpp"
#include "loopscan/io/errors.hpp"
#include "loopscan/io/signature_set.hpp"
#include "outputs/evaluation.hpp"

namespace loopscan::cli {
namespace {

struct BuildArgs {
  ConfigFlags config;
  std::string out;
  std::vector<std::string> signatures, gt;
  int first_session = 0;
};

struct QueryArgs {
  ConfigFlags config;
  std::string db, signatures, gt, out;
  std::vector<std::string> lanes;  // describe outputs of the same places from the next lanes
  int k = 5;
  std::vector<int> sessions;
  bool exact = false;
  bool same_session = false;  // the map holds these very places
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
  // The places keep how they were described (method, mode, frame: the sets' own metadata).
  std::vector<Described> described;
  for (const std::string& dir : a.signatures) described.push_back(read_described(dir));
  const Configuration c = resolve_configuration(a.config, described);
  if (c.image_baseline) throw std::invalid_argument("a place database holds sc, m2dp, delight or bev");
  DatabaseConfig config = database_config(c);
  if (const std::optional<DescriptorFrame> frame = described_frame(described)) config.frame = frame;
  Database db(config);
  for (std::size_t s = 0; s < a.signatures.size(); ++s) {
    io::SignatureSet set =
        io::load_signature_set(a.signatures[s], config.method, "", config.columns);
    if (!a.gt.empty()) io::attach_positions(set, a.gt[s]);
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
  std::printf("%s database (%s mode, %s frame): %zu places, %.1f KB per place in memory -> %s\n",
              method_name(config.method).c_str(), mode_name(c.mode).c_str(),
              descriptor_frame_name(*config.frame).c_str(), db.size(),
              db.size() ? double(db.memory_bytes()) / double(db.size()) / 1000.0 : 0.0,
              shown(a.out).c_str());
}

void run_query(const QueryArgs& a) {
  Database db = io::load_database(a.db);
  // The queries must be described as the map's places were (method, mode, frame).
  std::vector<Described> described = {described_map(a.db, db.config()),
                                      read_described(a.signatures)};
  for (const std::string& dir : a.lanes) described.push_back(read_described(dir));
  const Configuration c = resolve_configuration(a.config, described);
  if (db.config().method == Method::BirdsEye) db.set_birds_eye_search(c.birds_eye_search);
  io::SignatureSet queries =
      io::load_signature_set(a.signatures, db.config().method, "", db.config().columns);
  const bool with_gt = !a.gt.empty();
  if (with_gt) io::attach_positions(queries, a.gt);
  std::vector<io::SignatureSet> lanes;
  for (const std::string& dir : a.lanes) {
    lanes.push_back(io::load_signature_set(dir, db.config().method, "", db.config().columns));
    if (lanes.back().keyframe_ids != queries.keyframe_ids) {
      throw io::InputError(dir, 0,
                           "the keyframe ids of --signatures " + a.signatures +
                               " (a lane version describes the same places)");
    }
  }

  QueryOptions options = c.database.query;
  if (a.exact) options.retrieval = Retrieval::Exact;
  options.sessions = a.sessions;
  const eval::Protocol protocol =
      a.same_session ? c.evaluation.same_session : c.evaluation.cross_session;

  std::ostringstream csv;
  csv.precision(10);
  csv << "query_id,rank,session,keyframe,distance,yaw_deg,mirrored\n";
  std::vector<eval::QueryMatch> matches;
  double total_ms = 0;
  StepProgress progress("db query", "queries");
  for (std::size_t i = 0; i < queries.places.size(); ++i) {
    if (protocol.mask_width > 0) {  // the database holds this very sequence: skip its neighbours
      options.accept = outside_band(i, static_cast<std::size_t>(protocol.mask_width));
    }
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<Candidate> found;
    try {
      std::vector<PlaceDescriptor> versions;
      for (const io::SignatureSet& lane : lanes)
        versions.push_back({lane.places[i], lane.frames[i]});
      found = query_with_lane_versions(db, {queries.places[i], queries.frames[i]}, versions, a.k,
                                       options, lane_query_options(c));
    } catch (const std::invalid_argument& e) {
      throw io::InputError(a.signatures, 0, e.what());
    }
    total_ms +=
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    for (std::size_t r = 0; r < found.size(); ++r) {
      const Candidate& f = found[r];
      csv << queries.keyframe_ids[i] << ',' << r + 1 << ',' << f.place.session << ','
          << f.place.keyframe << ',' << f.distance << ',' << f.yaw_rad * 180.0 / M_PI << ','
          << (f.mirrored ? 1 : 0) << '\n';
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
              queries.places.size(), db.size(), query_ms, retrieval_name(options.retrieval).c_str(),
              shown(a.out).c_str());
  write_used_configuration(a.out, c);
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
    db_pos[j] = camera_centre(*T);
    db_headings[j] = T->leftCols<3>().row(2).transpose();  // the camera z axis in the world
    db_ids[j] = db.place(j).keyframe;
  }
  const eval::PrResult pr = eval::evaluate_matches(matches, queries.positions, db_pos, protocol);
  nlohmann::json metrics = {
      {"method", method_name(db.config().method)},
      {"fusion", fusion_name(db.config().fusion)},
      {"storage", storage_name(db.config().storage)},
      {"retrieval", retrieval_name(options.retrieval)},
      {"candidates", options.candidates},
      {"protocol", {{"threshold_m", protocol.threshold_m}, {"mask_width", protocol.mask_width}}},
      {"n_database", db.size()},
      {"query_ms", query_ms}};
  metrics.update(pr_metrics(pr));
  metrics["by_direction"] = direction_metrics(eval::split_by_direction(
      pr, queries.positions, db_pos, queries.headings, db_headings, protocol));
  const std::string title =
      method_name(db.config().method) + " database (" + retrieval_name(options.retrieval) + ")";
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
  build
      ->add_option("--signatures", b->signatures,
                   "describe output dir; repeat for more sessions (numbered in order)")
      ->required();
  build->add_option("--gt", b->gt, "ground truth per --signatures (stored as place positions)");
  build->add_option("--out", b->out, "database file")->required();
  build->add_option("--first-session", b->first_session, "session id of the first --signatures")
      ->check(finite_in(0, 1e6))
      ->capture_default_str();
  build->add_option("--method", b->config.method, "sc | m2dp | delight | bev (default: the sets' own)");
  add_mode_option(*build, b->config);
  add_config_option(*build, b->config);
  build->callback([b] {
    BuildArgs args = *b;
    const auto is_database = [](const std::string& p) { return starts_with_bytes(p, "LOOPSCDB"); };
    with_output_file(args.out, is_database, [&] { run_build(args); });
  });

  auto q = std::make_shared<QueryArgs>();
  CLI::App* query = db->add_subcommand("query", "Query a database with a described sequence");
  query->add_option("--db", q->db, "database file (db build)")->required();
  query->add_option("--signatures", q->signatures, "describe output dir of the queries")
      ->required();
  query->add_option("--gt", q->gt, "ground truth of the queries: adds metrics, PR curve");
  query->add_option("--out", q->out, "output directory")->required();
  query->add_option("--k", q->k, "results per query")
      ->check(finite_in(1, 10000))
      ->capture_default_str();
  query->add_flag("--exact", q->exact, "exact search instead of the index");
  query->add_option("--sessions", q->sessions, "only places of these sessions")
      ->check(finite_in(0, 1e6));
  query->add_flag("--same-session", q->same_session,
                  "the database holds these very places: evaluation.same_session's protocol, "
                  "its mask skips each query's neighbours (else evaluation.cross_session)");
  query->add_option("--lanes", q->lanes,
                    "describe outputs of the same places from the next lanes (sc, camera frame, "
                    "lateral_offset_m -3.5 / 3.5): they match reverse drives only");
  add_config_option(*query, q->config);
  run_writing_dir(query, q, run_query);
}

}  // namespace loopscan::cli
