#include "loopscan/baselines/inverted_index.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace loopscan::baselines {

int InvertedIndex::add(const BowVector& v) {
  for (const auto& [word, weight] : v) {
    if (word < 0 || word > kMaxWord) {
      throw std::invalid_argument("InvertedIndex::add: word id " + std::to_string(word) +
                                  " outside 0.." + std::to_string(kMaxWord));
    }
  }
  const int id = static_cast<int>(images_++);
  for (const auto& [word, weight] : v) {
    if (word >= static_cast<int>(postings_.size()))
      postings_.resize(static_cast<std::size_t>(word) + 1);
    postings_[word].images.push_back(id);
    postings_[word].weights.push_back(weight);
  }
  return id;
}

std::vector<BowMatch> InvertedIndex::query(const BowVector& q, int k,
                                           const std::function<bool(int)>& accept) const {
  // Dense accumulation over all images (a few thousand floats) instead of a touched list:
  // no branch in the posting loop.
  thread_local std::vector<float> score;
  score.assign(images_, 0.0f);
  for (const auto& [word, weight] : q) {
    if (word >= static_cast<int>(postings_.size())) continue;
    const Postings& p = postings_[word];
    const int* ids = p.images.data();
    const float* w = p.weights.data();
    for (std::size_t i = 0; i < p.images.size(); ++i) score[ids[i]] += std::min(weight, w[i]);
  }
  std::vector<BowMatch> out;
  for (std::size_t image = 0; image < images_; ++image) {
    const int id = static_cast<int>(image);
    if (score[image] > 0.0f && (!accept || accept(id))) out.push_back({id, score[image]});
  }
  const auto better = [](const BowMatch& a, const BowMatch& b) {
    return a.score != b.score ? a.score > b.score : a.image < b.image;
  };
  const std::size_t n = std::min(out.size(), static_cast<std::size_t>(std::max(k, 0)));
  std::partial_sort(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(n), out.end(), better);
  out.resize(n);
  return out;
}

}  // namespace loopscan::baselines
