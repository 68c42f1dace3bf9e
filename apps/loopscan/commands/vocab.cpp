// loopscan vocab train: a vocabulary tree from the ORB features of KITTI-layout sequences, in our
// binary format (or ORBvoc.txt's text format with --text).
#include <cstdio>
#include <fstream>

#include "cli/commands.hpp"
#include "cli/configuration.hpp"
#include "cli/options.hpp"
#include "cli/output_sets.hpp"
#include "loopscan/baselines/describe_images.hpp"
#include "loopscan/baselines/vocabulary_io.hpp"

namespace loopscan::cli {
namespace {

struct VocabArgs {
  ConfigFlags config;
  std::vector<std::string> kitti;
  std::string out;
  int step = 5;
  bool text = false;
};

void run_vocab_train(const VocabArgs& a) {
  if (a.step < 1) throw std::invalid_argument("--step must be at least 1");
  const Configuration c = resolve_configuration(a.config);
  const baselines::OrbConfig& orb = c.baselines.orb;
  const baselines::VocabularyConfig& vc = c.baselines.vocabulary;
  std::vector<cv::Mat> images;
  for (const std::string& dir : a.kitti) {
    const io::KittiSequence s = io::open_kitti_sequence(dir);
    for (cv::Mat& m : baselines::orb_of_sequence(s, a.step, orb)) images.push_back(std::move(m));
  }
  std::size_t descriptors = 0;
  for (const cv::Mat& m : images) descriptors += static_cast<std::size_t>(m.rows);
  std::printf("training on %zu images, %zu ORB descriptors (k %d, L %d) ...\n", images.size(),
              descriptors, vc.branching, vc.depth);
  std::fflush(stdout);
  const baselines::Vocabulary v = baselines::train_vocabulary(images, vc);
  if (a.text) {
    io::write_orbvoc_text(a.out, baselines::to_records(v));
  } else {
    io::save_vocabulary(a.out, baselines::to_records(v));
  }
  std::printf("%zu nodes, %zu words -> %s\n", v.nodes().size(), v.words(), shown(a.out).c_str());
}

}  // namespace

void add_vocab_command(CLI::App& app) {
  auto a = std::make_shared<VocabArgs>();
  CLI::App* vocab = app.add_subcommand("vocab", "Bag-of-Words vocabulary tools");
  vocab->require_subcommand(1);
  CLI::App* train = vocab->add_subcommand("train", "Train a vocabulary tree on ORB features");
  train->add_option("--kitti", a->kitti, "KITTI-layout sequence(s)")->required();
  train->add_option("--out", a->out, "vocabulary file")->required();
  train->add_option("--step", a->step, "use every step-th frame")
      ->check(finite_in(1, kMaxCount))
      ->capture_default_str();
  add_config_option(*train, a->config);
  train->add_flag("--text", a->text, "write ORBvoc.txt's text format instead of binary");
  train->callback([a] {
    VocabArgs args = *a;
    // A vocabulary in our binary format or ORBvoc.txt's (`k L scoring weighting` first).
    const auto is_vocabulary = [](const std::string& p) {
      std::ifstream in(p);
      int k = 0, depth = 0, scoring = 0, weighting = 0;
      return starts_with_bytes(p, "LSVOCAB1") ||
             static_cast<bool>(in >> k >> depth >> scoring >> weighting);
    };
    with_output_file(args.out, is_vocabulary, [&] { run_vocab_train(args); });
  });
}

}  // namespace loopscan::cli
