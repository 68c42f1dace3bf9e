// The image baselines: GIST (constant image, the filter bank's orientation and scale behaviour)
// and Bag-of-Words (k-majority, TF-IDF, the L1 score and the inverted index against brute force,
// vocabulary files in both formats including malformed ORBvoc.txt).
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

namespace loopscan {
namespace {

namespace fs = std::filesystem;
using baselines::BowVector;

// ---- GIST ----------------------------------------------------------------------------------

TEST(Gist, ConstantImageHasNoEnergy) {
  baselines::GistExtractor gist;
  const Eigen::VectorXf d = gist.describe(cv::Mat(200, 300, CV_8UC1, cv::Scalar(117)));
  ASSERT_EQ(d.size(), 512);
  EXPECT_LT(d.cwiseAbs().maxCoeff(), 1e-4f);
}

cv::Mat grating(double frequency, double angle_rad) {
  cv::Mat m(256, 256, CV_8UC1);
  const double fx = frequency * std::cos(angle_rad), fy = frequency * std::sin(angle_rad);
  for (int y = 0; y < 256; ++y)
    for (int x = 0; x < 256; ++x)
      m.at<std::uint8_t>(y, x) =
          cv::saturate_cast<std::uint8_t>(128 + 100 * std::cos(2 * M_PI * (fx * x + fy * y)));
  return m;
}

// Filter with the most energy, summed over the grid.
std::pair<int, int> strongest_filter(const Eigen::VectorXf& d, const baselines::GistConfig& c) {
  int best = 0;
  float best_e = -1;
  const int cells = c.grid * c.grid;
  for (int k = 0; k < c.scales * c.orientations; ++k) {
    const float e = d.segment(k * cells, cells).sum();
    if (e > best_e) {
      best_e = e;
      best = k;
    }
  }
  return {best / c.orientations, best % c.orientations};
}

TEST(Gist, GratingsSelectTheFilterOfTheirOrientationAndScale) {
  baselines::GistExtractor gist;
  const baselines::GistConfig& c = gist.config();
  const double step = M_PI / c.orientations;
  for (int s = 0; s < 3; ++s) {
    const double f = 0.3 / std::pow(1.85, s);
    for (int o = 0; o < c.orientations; ++o) {
      // Filter o peaks at angle -o * step in the frequency plane (either lobe of the grating).
      const auto [scale, orientation] = strongest_filter(gist.describe(grating(f, -o * step)), c);
      EXPECT_EQ(scale, s) << "scale " << s << " orientation " << o;
      EXPECT_EQ(orientation, o) << "scale " << s << " orientation " << o;
    }
  }
  // Rotating a grating by 45 degrees moves the response by two orientations; dividing its
  // frequency by 1.85 moves it one scale coarser.
  const auto a = strongest_filter(gist.describe(grating(0.162, -0.35)), c);
  const auto b = strongest_filter(gist.describe(grating(0.162, -0.35 - M_PI / 4)), c);
  const auto coarser = strongest_filter(gist.describe(grating(0.162 / 1.85, -0.35)), c);
  EXPECT_EQ(b.second, (a.second + 2) % c.orientations);
  EXPECT_EQ(coarser.first, a.first + 1);
  EXPECT_EQ(coarser.second, a.second);
}

TEST(Gist, FilterBankPeaksWhereDeclared) {
  baselines::GistConfig c;
  const int n = c.image_size + 2 * c.boundary;
  for (const baselines::GaborFilter& g : baselines::gabor_bank(c)) {
    const auto it = std::max_element(g.transfer.begin(), g.transfer.end());
    const int i = static_cast<int>(it - g.transfer.begin());
    auto freq = [n](int k) { return (k < n / 2 ? k : k - n) / static_cast<double>(n); };
    const double fx = freq(i % n), fy = freq(i / n);
    EXPECT_NEAR(std::hypot(fx, fy), g.peak_cycles_per_pixel, 1.5 / n) << g.scale << " " << g.orientation;
    double da = std::atan2(fy, fx) - g.angle_rad;
    da = std::remainder(da, 2 * M_PI);
    EXPECT_LT(std::abs(da), 0.15) << g.scale << " " << g.orientation;
    EXPECT_NEAR(*it, 1.0f, 0.05f);
  }
}

// ---- Bag of Words --------------------------------------------------------------------------

cv::Mat random_descriptors(int n, std::mt19937& rng) {
  cv::Mat m(n, 32, CV_8U);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < 32; ++c) m.at<std::uint8_t>(r, c) = static_cast<std::uint8_t>(rng() & 0xff);
  return m;
}

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
baselines::Vocabulary random_vocabulary(unsigned seed, int n_images, int per_image, int k, int L,
                                        std::vector<cv::Mat>* training = nullptr) {
  std::mt19937 rng(seed);
  std::vector<cv::Mat> images;
  for (int i = 0; i < n_images; ++i) images.push_back(random_descriptors(per_image, rng));
  baselines::VocabularyConfig config;
  config.branching = k;
  config.depth = L;
  if (training) *training = images;
  return baselines::train_vocabulary(images, config);
}

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
    for (int r = 0; r < images[i].rows; ++r) seen[v.word_of(images[i].ptr<std::uint8_t>(r))].insert(static_cast<int>(i));
  for (const baselines::VocabularyNode& n : nodes) {
    if (n.word < 0 || seen[n.word].empty()) continue;
    EXPECT_NEAR(n.weight, std::log(12.0 / seen[n.word].size()), 1e-5);
  }
  const BowVector b = v.transform(images[0]);
  double total = 0;
  for (std::size_t i = 0; i < b.size(); ++i) {
    total += b[i].second;
    if (i > 0) EXPECT_LT(b[i - 1].first, b[i].first);
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
  for (int f : {5, 40, 90, 130, 170, 210}) training.push_back(baselines::extract_orb(image(f), orb));
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

// ---- vocabulary files ----------------------------------------------------------------------

fs::path temp_file(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / "loopscan_vocab";
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
      {"10 6 0\n" + good, ":1"},                          // header: 3 numbers
      {"1 6 0 0\n" + good, "branching"},                  // k = 1
      {"10 6 9 0\n" + good, "scoring"},                   // unknown scoring
      {"10 6 0 0\n" + node_line(0, 1, 256, 1.0), ":2"},   // byte out of range
      {"10 6 0 0\n" + good + "0 1 5\n", ":3"},            // short line
      {"10 6 0 0\n" + node_line(3, 1, 1, 1.0), "parent"}, // forward reference
      {"10 6 0 0\n" + good + node_line(1, 1, 1, 1.0), "leaf"},  // child of a word
      {"10 6 0 0\n" + node_line(0, 2, 1, 1.0), "is_leaf"},
      {"10 6 0 0\n" + node_line(0, 1, 1, -1.0), "weight"},
      {"10 6 0 0\n" + good + "x" + good, ":3"},
      {"10 6 0 0\n", "node line"},                        // no nodes
  };
  for (const auto& [text, expected] : cases) {
    const fs::path p = temp_file("bad.txt");
    std::ofstream(p) << text;
    const std::string e = error_of(p.string());
    EXPECT_NE(e.find(expected), std::string::npos) << "got: " << e << "\nfor:\n" << text.substr(0, 60);
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
