// Vocabulary files: a hand-made ORBvoc.txt, malformed text naming the line, round trips and
// damaged binary files.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "support/rendered_street.hpp"

#include "loopscan/baselines/gist.hpp"
#include "loopscan/baselines/inverted_index.hpp"
#include "loopscan/baselines/orb_features.hpp"
#include "loopscan/baselines/vocabulary.hpp"
#include "loopscan/baselines/vocabulary_io.hpp"
#include "loopscan/io/errors.hpp"
#include "loopscan/sim/renderer.hpp"
#include "loopscan/sim/trajectory.hpp"
#include "support/random_vocabulary.hpp"
#include "support/test_support.hpp"
namespace loopscan {
namespace {

namespace fs = std::filesystem;
using baselines::BowVector;
using test::random_vocabulary;

fs::path temp_file(const std::string& name) {
  const fs::path d = test::temp_path("vocab");
  fs::create_directories(d);
  return d / name;
}

std::string node_line(int parent, int leaf, int byte, double weight) {
  std::string s = std::to_string(parent) + " " + std::to_string(leaf);
  for (int i = 0; i < 32; ++i) s += " " + std::to_string(i == 0 ? byte : 0);
  return s + " " + std::to_string(weight) + "\n";
}

std::string error_of(const std::string& path) {
  try {
    baselines::read_vocabulary(path);
  } catch (const io::InputError& e) {
    return e.what();
  } catch (const std::invalid_argument& e) {
    return std::string("invalid_argument: ") + e.what();
  }
  return "accepted";
}

TEST(VocabularyFile, ReadsAHandMadeOrbVocText) {
  // Root -> 2 inner nodes (bytes 0x00, 0xF0) -> 2 words each; words weigh 0.5 .. 2.0.
  const fs::path p = temp_file("small.txt");
  std::ofstream(p) << "2 2 0 0\n"
                   << node_line(0, 0, 0x00, 0) << node_line(0, 0, 0xF0, 0)
                   << node_line(1, 1, 0x01, 0.5) << node_line(1, 1, 0x03, 1.0)
                   << node_line(2, 1, 0xF0, 1.5) << node_line(2, 1, 0xFF, 2.0);
  const baselines::Vocabulary v = baselines::read_vocabulary(p.string());
  EXPECT_EQ(v.branching, 2);
  EXPECT_EQ(v.depth, 2);
  ASSERT_EQ(v.words(), 4u);
  EXPECT_EQ(v.children(0), (std::vector<int>{1, 2}));
  EXPECT_EQ(v.children(2), (std::vector<int>{5, 6}));
  std::uint8_t d[32] = {0xFE};
  EXPECT_EQ(v.word_of(d), 3);  // 0xFE: branch 0xF0, then closer to 0xFF than to 0xF0
  d[0] = 0x01;
  EXPECT_EQ(v.word_of(d), 0);
  EXPECT_FLOAT_EQ(v.nodes()[6].weight, 2.0f);

  // Round trips: binary and text give the same nodes.
  const fs::path bin = temp_file("small.bin"), txt = temp_file("small2.txt");
  io::save_vocabulary(bin.string(), baselines::to_records(v));
  io::write_orbvoc_text(txt.string(), baselines::to_records(v));
  for (const fs::path& f : {bin, txt}) {
    const baselines::Vocabulary w = baselines::read_vocabulary(f.string());
    ASSERT_EQ(w.nodes().size(), v.nodes().size()) << f;
    for (std::size_t i = 0; i < v.nodes().size(); ++i) {
      EXPECT_EQ(w.nodes()[i].parent, v.nodes()[i].parent);
      EXPECT_EQ(w.nodes()[i].descriptor, v.nodes()[i].descriptor);
      EXPECT_EQ(w.nodes()[i].weight, v.nodes()[i].weight);
      EXPECT_EQ(w.nodes()[i].word, v.nodes()[i].word);
    }
  }
}

TEST(VocabularyFile, MalformedOrbVocTextNamesTheLine) {
  const std::string good = node_line(0, 1, 1, 1.0);
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"10 6 0\n" + good, ":1"},                                // header: 3 numbers
      {"1 6 0 0\n" + good, "branching"},                        // k = 1
      {"10 6 9 0\n" + good, "scoring"},                         // unknown scoring
      {"10 6 0 0\n" + node_line(0, 1, 256, 1.0), ":2"},         // byte out of range
      {"10 6 0 0\n" + good + "0 1 5\n", ":3"},                  // short line
      {"10 6 0 0\n" + node_line(3, 1, 1, 1.0), "parent"},       // forward reference
      {"10 6 0 0\n" + good + node_line(1, 1, 1, 1.0), "leaf"},  // child of a word
      {"10 6 0 0\n" + node_line(0, 2, 1, 1.0), "is_leaf"},
      {"10 6 0 0\n" + node_line(0, 1, 1, -1.0), "weight"},
      {"10 6 0 0\n" + good + "x" + good, ":3"},
      {"10 6 0 0\n", "node line"},  // no nodes
  };
  for (const auto& [text, expected] : cases) {
    const fs::path p = temp_file("bad.txt");
    std::ofstream(p) << text;
    const std::string e = error_of(p.string());
    EXPECT_NE(e.find(expected), std::string::npos) << "got: " << e << "\nfor:\n"
                                                   << text.substr(0, 60);
    EXPECT_NE(e.find("bad.txt"), std::string::npos) << e;
  }
}

TEST(VocabularyFile, DamagedBinaryFilesAreRejected) {
  std::mt19937 rng(7);
  const fs::path p = temp_file("v.bin");
  io::save_vocabulary(p.string(), baselines::to_records(random_vocabulary(7, 4, 60, 3, 2)));
  std::ifstream in(p, std::ios::binary);
  const std::string good((std::istreambuf_iterator<char>(in)), {});
  int rejected = 0, trials = 0;
  for (int t = 0; t < 120; ++t) {
    std::string bad = good;
    if (t % 2 == 0) {
      bad.resize(rng() % good.size());
    } else {
      bad[rng() % bad.size()] ^= static_cast<char>(1 + rng() % 255);
    }
    const fs::path q = temp_file("damaged.bin");
    std::ofstream(q, std::ios::binary) << bad;
    ++trials;
    const std::string e = error_of(q.string());
    if (e != "accepted") ++rejected;
    EXPECT_EQ(e.find("invalid_argument"), std::string::npos) << e;
  }
  EXPECT_EQ(rejected, trials);
}

}  // namespace
}  // namespace loopscan
