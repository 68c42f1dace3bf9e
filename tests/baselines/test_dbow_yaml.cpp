// DBoW2 / DBoW3 vocabularies in OpenCV YAML (../shared/data/real/vocabularies): structure,
// weights, descent, the slambook loop (image 1 matches image 10), malformed files.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "loopscan/baselines/orb_features.hpp"
#include "loopscan/baselines/vocabulary.hpp"
#include "loopscan/baselines/vocabulary_io.hpp"
#include "loopscan/io/errors.hpp"
#include "support/input_errors.hpp"
#include "support/test_support.hpp"

namespace loopscan::baselines {
namespace {
namespace fs = std::filesystem;

fs::path vocabularies() { return fs::path(test::shared_dir()) / "data/real/vocabularies"; }

struct Expected {
  const char* file;
  int k, L;
  std::size_t words;
};

TEST(DbowYaml, ReadsDbow2AndDbow3Vocabularies) {
  const fs::path dir = vocabularies();
  LOOPSCAN_SKIP_WITHOUT_SHARED(fs::exists(dir), dir);
  for (const Expected& e : {Expected{"dbow2-small/small_voc.yml.gz", 9, 3, 692},
                            Expected{"dbow3-slambook/vocabulary.yml.gz", 10, 5, 4983}}) {
    const Vocabulary v = read_vocabulary((dir / e.file).string());
    EXPECT_EQ(v.branching, e.k) << e.file;
    EXPECT_EQ(v.depth, e.L) << e.file;
    EXPECT_EQ(v.scoring, 0);
    EXPECT_EQ(v.weighting, 0);
    EXPECT_EQ(v.words(), e.words) << e.file;
    // Words are leaves with a positive IDF weight; inner nodes have children, at most k.
    std::size_t positive = 0;
    for (std::size_t i = 1; i < v.nodes().size(); ++i) {
      const VocabularyNode& n = v.nodes()[i];
      EXPECT_EQ(n.word >= 0, v.children(static_cast<int>(i)).empty()) << e.file << " node " << i;
      EXPECT_LE(v.children(static_cast<int>(i)).size(), static_cast<std::size_t>(e.k));
      EXPECT_TRUE(n.weight >= 0 && std::isfinite(n.weight)) << e.file << " node " << i;
      positive += n.word >= 0 && n.weight > 0;
    }
    // IDF log(N / N_i) is 0 for a word seen in every training image: measured 609 / 692 and
    // 4145 / 4983 words with a positive weight.
    EXPECT_GT(positive, e.words * 8 / 10) << e.file;
    // A word's own descriptor descends to that word (greedy Hamming descent, DBoW2's rule) for
    // most words (measured 87 % and 82 %: a k-majority centroid is not always nearest to its
    // own ancestors at every level).
    std::size_t home = 0;
    for (std::size_t i = 1; i < v.nodes().size(); ++i) {
      const VocabularyNode& n = v.nodes()[i];
      if (n.word >= 0) home += v.word_of(n.descriptor.data()) == n.word;
    }
    EXPECT_GT(home, e.words * 3 / 4) << e.file << ": " << home << " of " << e.words;
  }
}

TEST(DbowYaml, SlambookImageOneMatchesImageTen) {
  const fs::path dir = vocabularies() / "dbow3-slambook";
  LOOPSCAN_SKIP_WITHOUT_SHARED(fs::exists(dir / "data/1.png"), dir);
  const Vocabulary v = read_vocabulary((dir / "vocabulary.yml.gz").string());
  std::vector<BowVector> bow;
  for (int i = 1; i <= 10; ++i) {
    const cv::Mat image =
        cv::imread((dir / "data" / (std::to_string(i) + ".png")).string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(image.empty()) << i;
    OrbConfig orb;
    orb.features = 500;  // as slambook's demo
    bow.push_back(v.transform(extract_orb(image, orb)));
  }
  int best = -1;
  double best_score = -1;
  for (int j = 1; j < 10; ++j) {
    const double s = l1_score(bow[0], bow[j]);
    if (s > best_score) best_score = s, best = j + 1;
  }
  EXPECT_EQ(best, 10) << "image 1's best match (score " << best_score << ")";
}

std::string gz(const std::string& name, const std::string& text) {
  const fs::path dir = test::temp_path("dbow_yaml");
  fs::create_directories(dir);
  const std::string path = (dir / name).string();
  gzFile f = gzopen(path.c_str(), "wb");
  gzwrite(f, text.data(), static_cast<unsigned>(text.size()));
  gzclose(f);
  return path;
}

TEST(DbowYaml, MalformedVocabulariesNameTheFile) {
  const std::string head =
      "%YAML:1.0\n---\nvocabulary:\n   k: 2\n   L: 1\n   scoringType: 0\n   weightingType: 0\n"
      "   nodes:\n      - { nodeId:1, parentId:0, weight:1.,\n          descriptor:\"";
  const std::string bytes32 =
      "1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21 22 23 24 25 26 27 28 29 30 31 32";
  const std::string tail = "\" }\n   words:\n      - { wordId:0, nodeId:1 }\n";
  EXPECT_EQ(read_vocabulary(gz("ok_voc.yml.gz", head + bytes32 + tail)).words(), 1u);
  const std::pair<std::string, std::string> bad[] = {
      {gz("short_desc.yml.gz", head + "1 2 3" + tail), "32-byte ORB descriptor, found 3"},
      {gz("truncated.yml.gz", head.substr(0, head.size() - 40)), "truncated.yml.gz"},
      {gz("no_words.yml.gz", head + bytes32 + "\" }\n"), "nodes and words"},
      {gz("big_byte.yml.gz", head + "300" + bytes32.substr(1) + tail), "bytes 0..255"}};
  for (const auto& [path, fragment] : bad)
    test::expect_input_error([](const std::string& p) { read_vocabulary(p); }, path, fragment);
}

}  // namespace
}  // namespace loopscan::baselines
