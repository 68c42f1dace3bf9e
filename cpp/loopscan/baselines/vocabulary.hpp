#pragma once
// A vocabulary tree of binary (ORB, 32-byte) descriptors as in DBoW2: hierarchical k-majority
// clustering (branching k, depth L), leaves are the words, TF-IDF weights, L1-normalised
// Bag-of-Words vectors and DBoW2's L1 score.
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

namespace loopscan::baselines {

using Descriptor = std::array<std::uint8_t, 32>;

int hamming(const Descriptor& a, const std::uint8_t* b);

// Sorted by word id, weights L1-normalised (sum 1) unless empty.
using BowVector = std::vector<std::pair<int, float>>;

// DBoW2's L1 score 1 - |a - b|_1 / 2 of two L1-normalised vectors: 1 for identical vectors,
// 0 without a common word.
double l1_score(const BowVector& a, const BowVector& b);

struct VocabularyNode {
  int parent = -1;  // -1 for the root (node 0)
  Descriptor descriptor{};
  float weight = 0;  // IDF weight (words only)
  int word = -1;     // word id of a leaf, -1 for inner nodes
};

struct VocabularyConfig {
  int branching = 10, depth = 6;
  int iterations = 10;  // k-majority refinement rounds per node
  unsigned seed = 1;
};

class Vocabulary {
 public:
  // DBoW2's codes: scoring 0 = L1, weighting 0 = TF-IDF (the only ones this class scores with;
  // others are kept when read from a file, and `transform` refuses them).
  int branching = 10, depth = 6, scoring = 0, weighting = 0;

  Vocabulary() = default;
  // Nodes in any order where every parent precedes its children (node 0 = root).
  Vocabulary(int branching, int depth, int scoring, int weighting, std::vector<VocabularyNode> nodes);

  const std::vector<VocabularyNode>& nodes() const { return nodes_; }
  std::size_t words() const { return word_nodes_.size(); }
  const std::vector<int>& children(int node) const { return children_[node]; }

  // The word a descriptor falls into (greedy descent by Hamming distance).
  int word_of(const std::uint8_t* descriptor) const;
  // Descriptors (Nx32 CV_8U) -> TF-IDF BoW vector.
  BowVector transform(const cv::Mat& descriptors) const;

 private:
  std::vector<VocabularyNode> nodes_;
  std::vector<std::vector<int>> children_;
  std::vector<int> word_nodes_;
};

// Trains on the descriptors of each training image (one Nx32 CV_8U matrix per image); IDF
// weights log(images / images containing the word).
Vocabulary train_vocabulary(const std::vector<cv::Mat>& images, const VocabularyConfig& config);

}  // namespace loopscan::baselines
