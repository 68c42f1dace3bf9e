#pragma once
// An inverted index over BoW vectors (word -> images and weights): a query touches only the
// images sharing a word with it and accumulates DBoW2's L1 score on the way.
#include <functional>
#include <vector>

#include "loopscan/baselines/vocabulary.hpp"

namespace loopscan::baselines {

struct BowMatch {
  int image = -1;
  double score = 0;  // L1 score, 1 = identical
};

class InvertedIndex {
 public:
  explicit InvertedIndex(std::size_t words = 0) : postings_(words) {}
  // Returns the image id (0, 1, ...). Throws std::invalid_argument for a negative word id or one
  // above kMaxWord (the postings table grows to the largest word id).
  int add(const BowVector& v);
  static constexpr int kMaxWord = (1 << 24) - 1;
  std::size_t size() const { return images_; }
  // The k best images by score (ties: lower id first) among those `accept` allows (all if empty).
  std::vector<BowMatch> query(const BowVector& q, int k,
                              const std::function<bool(int)>& accept = {}) const;

 private:
  struct Postings {  // images containing the word and its weight in each (parallel arrays)
    std::vector<int> images;
    std::vector<float> weights;
  };
  std::vector<Postings> postings_;
  std::size_t images_ = 0;
};

}  // namespace loopscan::baselines
