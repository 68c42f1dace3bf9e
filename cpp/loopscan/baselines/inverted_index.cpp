#include "loopscan/baselines/inverted_index.hpp"

#include <algorithm>

namespace loopscan::baselines {

int InvertedIndex::add(const BowVector& v) {
  const int id = static_cast<int>(images_++);
  for (const auto& [word, weight] : v) {
    if (word >= static_cast<int>(postings_.size())) postings_.resize(static_cast<std::size_t>(word) + 1);
    postings_[word].push_back({id, weight});
  }
  return id;
}

std::vector<BowMatch> InvertedIndex::query(const BowVector& q, int k,
                                           const std::function<bool(int)>& accept) const {
  std::vector<double> score(images_, 0.0);
  std::vector<int> touched;
  for (const auto& [word, weight] : q) {
    if (word >= static_cast<int>(postings_.size())) continue;
    for (const Posting& p : postings_[word]) {
      if (score[p.image] == 0.0) touched.push_back(p.image);
      score[p.image] += std::min(weight, p.weight);
    }
  }
  std::vector<BowMatch> out;
  for (int image : touched)
    if (!accept || accept(image)) out.push_back({image, score[image]});
  const auto better = [](const BowMatch& a, const BowMatch& b) {
    return a.score != b.score ? a.score > b.score : a.image < b.image;
  };
  const std::size_t n = std::min(out.size(), static_cast<std::size_t>(std::max(k, 0)));
  std::partial_sort(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(n), out.end(), better);
  out.resize(n);
  return out;
}

}  // namespace loopscan::baselines
