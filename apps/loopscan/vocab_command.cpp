// loopscan vocab train: a vocabulary tree from the ORB features of KITTI-layout sequences, in our
// binary format (or ORBvoc.txt's text format with --text).
#include <cstdio>
#include <fstream>

#include "commands.hpp"
#include "loopscan/baselines/describe_images.hpp"
#include "loopscan/baselines/vocabulary_io.hpp"
#include "options.hpp"
#include "output_sets.hpp"

namespace loopscan::cli {
namespace {

struct VocabArgs {
  std::vector<std::string> kitti;
  std::string out;
  int branching = 10, depth = 6, features = 4000, step = 5, iterations = 10;
  unsigned seed = 1;
  bool text = false;
};

void run_vocab_train(const VocabArgs& a) {
  if (a.step < 1) throw std::invalid_argument("--step must be at least 1");
  baselines::OrbConfig orb;
  orb.features = a.features;
  std::vector<cv::Mat> images;
  for (const std::string& dir : a.kitti) {
    const io::KittiSequence s = io::open_kitti_sequence(dir);
    for (cv::Mat& m : baselines::orb_of_sequence(s, a.step, orb)) images.push_back(std::move(m));
  }
  std::size_t descriptors = 0;
  for (const cv::Mat& m : images) descriptors += static_cast<std::size_t>(m.rows);
  std::printf("training on %zu images, %zu ORB descriptors (k %d, L %d) ...\n", images.size(),
              descriptors, a.branching, a.depth);
  std::fflush(stdout);
  baselines::VocabularyConfig vc;
  vc.branching = a.branching;
  vc.depth = a.depth;
  vc.iterations = a.iterations;
  vc.seed = a.seed;
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
  train->add_option("--k", a->branching, "branching factor")
      ->check(finite_in(2, 100))
      ->capture_default_str();
  train->add_option("--depth", a->depth, "levels")->check(finite_in(1, 10))->capture_default_str();
  train->add_option("--features", a->features, "ORB features per image")
      ->check(finite_in(1, 100000))
      ->capture_default_str();
  train->add_option("--step", a->step, "use every step-th frame")
      ->check(finite_in(1, kMaxCount))
      ->capture_default_str();
  train->add_option("--iterations", a->iterations, "k-majority rounds per node")
      ->check(finite_in(1, 1000))
      ->capture_default_str();
  train->add_option("--seed", a->seed, "clustering seed")->capture_default_str();
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
