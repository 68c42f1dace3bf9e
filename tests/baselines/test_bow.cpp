// Bag-of-Words: the L1 score and the inverted index against brute force, the k-majority
// tree's IDF weights, rendered images scored against themselves and other streets.
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
namespace loopscan {
namespace {

namespace fs = std::filesystem;
using baselines::BowVector;
using test::random_descriptors;
using test::random_vocabulary;

BowVector random_bow(std::mt19937& rng, int words, int entries) {
  std::map<int, float> m;
  for (int i = 0; i < entries; ++i) m[static_cast<int>(rng() % words)] += 1.0f + (rng() % 5);
  float total = 0;
  for (auto& e : m) total += e.second;
  BowVector v;
  for (auto& e : m) v.emplace_back(e.first, e.second / total);
  return v;
}

double dense_l1_score(const BowVector& a, const BowVector& b, int words) {
  std::vector<double> x(words, 0), y(words, 0);
  for (auto& e : a) x[e.first] = e.second;
  for (auto& e : b) y[e.first] = e.second;
  double d = 0;
  for (int i = 0; i < words; ++i) d += std::abs(x[i] - y[i]);
  return 1.0 - 0.5 * d;
}

TEST(Bow, L1ScoreAndInvertedIndexMatchBruteForce) {
  std::mt19937 rng(3);
  std::vector<BowVector> db;
  baselines::InvertedIndex index(500);
  for (int i = 0; i < 300; ++i) {
    db.push_back(random_bow(rng, 500, 60));
    EXPECT_EQ(index.add(db.back()), i);
  }
  for (int q = 0; q < 20; ++q) {
    const BowVector query = random_bow(rng, 500, 60);
    EXPECT_NEAR(baselines::l1_score(query, query), 1.0, 1e-6);
    std::vector<std::pair<double, int>> brute;
    for (int i = 0; i < 300; ++i) {
      const double s = dense_l1_score(query, db[i], 500);
      EXPECT_NEAR(baselines::l1_score(query, db[i]), s, 1e-5);
      if (i % 2 == 0) brute.push_back({-s, i});  // only even images accepted
    }
    std::sort(brute.begin(), brute.end());
    const auto top = index.query(query, 5, [](int i) { return i % 2 == 0; });
    ASSERT_EQ(top.size(), 5u);
    for (int r = 0; r < 5; ++r) {
      EXPECT_NEAR(top[r].score, -brute[r].first, 1e-5);
      EXPECT_EQ(top[r].image % 2, 0);
    }
  }
  EXPECT_EQ(baselines::l1_score({{1, 1.0f}}, {{2, 1.0f}}), 0.0);
}

// A vocabulary trained on `n_images` images of random descriptors.

TEST(Bow, TrainedTreeIsAKMajorityHierarchyWithIdfWeights) {
  std::vector<cv::Mat> images;
  const baselines::Vocabulary v = random_vocabulary(5, 12, 150, 4, 3, &images);
  const auto& nodes = v.nodes();
  std::size_t leaves = 0;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    EXPECT_LE(v.children(static_cast<int>(i)).size(), 4u);
    int depth = 0;
    for (int p = static_cast<int>(i); p != 0; p = nodes[p].parent) ++depth;
    EXPECT_LE(depth, 3);
    if (nodes[i].word >= 0) {
      ++leaves;
      EXPECT_TRUE(v.children(static_cast<int>(i)).empty());
    }
  }
  EXPECT_EQ(leaves, v.words());
  EXPECT_GT(v.words(), 30u);
  // IDF by brute force: log(images / images containing the word).
  std::vector<std::set<int>> seen(v.words());
  for (std::size_t i = 0; i < images.size(); ++i)
    for (int r = 0; r < images[i].rows; ++r)
      seen[v.word_of(images[i].ptr<std::uint8_t>(r))].insert(static_cast<int>(i));
  for (const baselines::VocabularyNode& n : nodes) {
    if (n.word < 0 || seen[n.word].empty()) continue;
    EXPECT_NEAR(n.weight, std::log(12.0 / seen[n.word].size()), 1e-5);
  }
  const BowVector b = v.transform(images[0]);
  double total = 0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    total += b[i].second;
    if (i > 0) {
      EXPECT_LT(b[i - 1].first, b[i].first);
    }
  }
  EXPECT_NEAR(total, 1.0, 1e-5);
  EXPECT_NEAR(baselines::l1_score(b, b), 1.0, 1e-6);
}

TEST(Bow, ImageScoresOneWithItselfAndLowWithAnotherPlace) {
  const test::ShortStreet street(0.5);
  auto image = [&](int frame) { return street.render(frame, 0); };
  baselines::OrbConfig orb;
  orb.features = 1000;
  std::vector<cv::Mat> training;
  for (int f : {5, 40, 90, 130, 170, 210})
    training.push_back(baselines::extract_orb(image(f), orb));
  baselines::VocabularyConfig vc;
  vc.branching = 8;
  vc.depth = 4;
  const baselines::Vocabulary v = baselines::train_vocabulary(training, vc);
  const BowVector a = v.transform(baselines::extract_orb(image(60), orb));
  const BowVector a_next = v.transform(baselines::extract_orb(image(61), orb));
  const BowVector far = v.transform(baselines::extract_orb(image(150), orb));
  EXPECT_NEAR(baselines::l1_score(a, a), 1.0, 1e-5);
  const double same_place = baselines::l1_score(a, a_next), other = baselines::l1_score(a, far);
  std::printf("BoW score: itself 1, next frame %.3f, another street %.3f\n", same_place, other);
  EXPECT_LT(other, 0.3);
  EXPECT_GT(same_place, other + 0.1);
}

TEST(Bow, InvertedIndexRefusesWordIdsBeyondItsTable) {
  baselines::InvertedIndex index;
  EXPECT_THROW(index.add({{3, 0.5f}, {1 << 30, 0.5f}}), std::invalid_argument);
  EXPECT_THROW(index.add({{-1, 0.5f}}), std::invalid_argument);
  EXPECT_EQ(index.size(), 0u);  // nothing half-added
  EXPECT_EQ(index.add({{3, 0.5f}, {baselines::InvertedIndex::kMaxWord, 0.5f}}), 0);
}

}  // namespace
}  // namespace loopscan
