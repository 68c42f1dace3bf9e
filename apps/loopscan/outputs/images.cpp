#include "outputs/images.hpp"

#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "cli/configuration.hpp"
#include "cli/output_sets.hpp"
#include "loopscan/baselines/baseline_matching.hpp"
#include "loopscan/baselines/describe_images.hpp"
#include "loopscan/baselines/vocabulary_io.hpp"
#include "loopscan/eval/precision_recall.hpp"
#include "loopscan/io/atomic_file.hpp"
#include "loopscan/io/bow_file.hpp"
#include "loopscan/io/errors.hpp"
#include "loopscan/io/incoming_ids.hpp"
#include "loopscan/io/matrix_text.hpp"
#include "loopscan/io/signature_set.hpp"
#include "outputs/evaluation.hpp"

namespace loopscan::cli {
namespace {

struct ImageSet {
  std::vector<Eigen::VectorXf> gist;
  std::vector<baselines::BowVector> bow;
  std::vector<int> ids;
  std::vector<Eigen::Vector3d> positions;
  std::size_t size() const { return ids.size(); }
};

ImageSet load_image_set(const std::string& dir, const std::string& method) {
  ImageSet s;
  s.ids = io::read_incoming_ids(dir + "/incoming_id_file.txt");
  std::size_t n = 0;
  std::string file;
  if (method == "gist") {
    file = dir + "/signatures.txt";
    const Eigen::MatrixXd m = io::read_matrix_text(file);
    for (Eigen::Index r = 0; r < m.rows(); ++r)
      s.gist.push_back(m.row(r).transpose().cast<float>());
    n = s.gist.size();
  } else {
    file = dir + "/bow.txt";
    s.bow = io::read_bow_vectors(file);
    n = s.bow.size();
  }
  if (n != s.ids.size()) {
    throw io::InputError(file, 0,
                         "one place per keyframe id of incoming_id_file.txt (" +
                             std::to_string(s.ids.size()) + " ids, " + std::to_string(n) +
                             " places)");
  }
  return s;
}

}  // namespace

bool is_image_method(const std::string& method) { return method == "gist" || method == "bow"; }

void write_image_descriptors(const std::string& dir, const baselines::ImageDescriptors& d,
                             const std::vector<int>& ids, const Configuration& c) {
  std::filesystem::create_directories(dir);
  if (c.image_baseline == ImageBaseline::Gist) {
    Eigen::MatrixXd m(static_cast<Eigen::Index>(d.gist.size()),
                      d.gist.empty() ? 512 : d.gist[0].size());
    for (std::size_t i = 0; i < d.gist.size(); ++i)
      m.row(static_cast<Eigen::Index>(i)) = d.gist[i].cast<double>().transpose();
    io::write_matrix_text(dir + "/signatures.txt", m);
  } else {
    io::write_bow_vectors(dir + "/bow.txt", d.bow);
  }
  io::write_incoming_ids(dir + "/incoming_id_file.txt", ids);
  write_used_configuration(dir, c);
}

void run_image_describe(const ImageDescribeArgs& a, const Configuration& c) {
  const std::string method = method_name(c);
  if (a.kitti.empty() || a.keyframes.empty())
    throw std::invalid_argument("--method " + method + " needs --kitti and --keyframes");
  if (method == "bow" && a.vocab.empty()) throw std::invalid_argument("--method bow needs --vocab");
  const io::KittiSequence sequence = io::open_kitti_sequence(a.kitti);
  const std::vector<int> ids = io::read_incoming_ids(a.keyframes + "/incoming_id_file.txt");
  baselines::ImageDescriptors d;
  if (method == "gist") {
    d = baselines::describe_gist(sequence, ids, gist_config(c), a.threads);
  } else {
    const baselines::Vocabulary vocabulary = baselines::read_vocabulary(a.vocab);
    d = baselines::describe_bow(sequence, ids, vocabulary, c.baselines.orb);
  }
  write_image_descriptors(a.out, d, ids, c);
  const nlohmann::json timing = {{"method", method},
                                 {"mode", mode_name(c.mode)},
                                 {"sequence", a.kitti},
                                 {"n_keyframes", ids.size()},
                                 {"read_ms", d.read_ms},
                                 {"extract_ms", d.extract_ms},
                                 {"transform_ms", d.transform_ms},
                                 {"describe_ms", d.extract_ms + d.transform_ms},
                                 {"mean_features", d.mean_features},
                                 {"vocabulary", a.vocab}};
  io::write_file_atomic(a.out + "/timing.json", timing.dump(1) + "\n");
  std::printf("%s: %zu keyframes; %.2f ms extract + %.2f ms transform per image -> %s\n",
              method.c_str(), ids.size(), d.extract_ms, d.transform_ms, shown(a.out).c_str());
}

void run_image_evaluate(const ImageEvaluateArgs& a, const Configuration& c) {
  const std::string method = method_name(c);
  ImageSet queries = load_image_set(a.signatures, method);
  queries.positions = io::positions_of(queries.ids, a.gt);
  const bool cross = !a.against.empty();
  ImageSet db = queries;
  if (cross) {
    if (a.gt2.empty()) throw std::invalid_argument("--against needs --gt2");
    db = load_image_set(a.against, method);
    db.positions = io::positions_of(db.ids, a.gt2);
  }
  if (queries.size() == 0 || db.size() == 0)
    throw std::invalid_argument("nothing to evaluate: no places in " +
                                (queries.size() == 0 ? a.signatures : a.against));
  const eval::Protocol protocol = cross ? c.evaluation.cross_session : c.evaluation.same_session;
  const baselines::BaselineMatches m =
      method == "gist" ? baselines::best_gist_matches(queries.gist, db.gist, protocol.mask_width)
                       : baselines::best_bow_matches(queries.bow, db.bow, protocol.mask_width);
  const eval::PrResult pr = eval::evaluate_matches(m.matches, queries.positions, db.positions,
                                                   protocol, c.mode == Mode::Reference);
  nlohmann::json metrics = {{"method", method},
                            {"mode", mode_name(c.mode)},
                            {"protocol",
                             {{"threshold_m", protocol.threshold_m},
                              {"mask_width", protocol.mask_width},
                              {"cross_session", cross}}},
                            {"n_database", db.size()},
                            {"query_ms", m.query_ms}};
  metrics.update(pr_metrics(pr));
  write_evaluation(a.out, queries.ids, db.ids, pr, metrics, method);
  write_used_configuration(a.out, c);
  std::printf(
      "%s: AUC %.4f, recall@100%%P %.4f, F1-max %.4f, %d GT loops / %d queries, %.3f ms per query "
      "-> %s\n",
      method.c_str(), pr.auc, pr.recall_at_100_precision, pr.f1_max, pr.n_gt_loops, pr.n_queries,
      m.query_ms, shown(a.out).c_str());
}

}  // namespace loopscan::cli
