#include "loopscan/baselines/vocabulary.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>

namespace loopscan::baselines {
namespace {

Descriptor to_descriptor(const std::uint8_t* p) {
  Descriptor d;
  std::memcpy(d.data(), p, 32);
  return d;
}

// Bitwise majority of the members (ties -> 0, as DBoW2's binary mean).
Descriptor majority(const std::vector<const std::uint8_t*>& members) {
  int counts[256] = {};
  for (const std::uint8_t* m : members)
    for (int bit = 0; bit < 256; ++bit) counts[bit] += (m[bit / 8] >> (7 - bit % 8)) & 1;
  Descriptor d{};
  for (int bit = 0; bit < 256; ++bit)
    if (2 * counts[bit] > static_cast<int>(members.size())) d[bit / 8] |= static_cast<std::uint8_t>(1 << (7 - bit % 8));
  return d;
}

// k-majority of `members` with k-means++ seeding; returns the clusters' centres and members.
void cluster(const std::vector<const std::uint8_t*>& members, int k, int iterations,
             std::mt19937& rng, std::vector<Descriptor>& centres,
             std::vector<std::vector<const std::uint8_t*>>& groups) {
  centres.clear();
  groups.clear();
  if (static_cast<int>(members.size()) <= k) {  // every descriptor its own cluster
    for (const std::uint8_t* m : members) {
      centres.push_back(to_descriptor(m));
      groups.push_back({m});
    }
    return;
  }
  std::vector<double> nearest(members.size(), std::numeric_limits<double>::max());
  centres.push_back(to_descriptor(members[std::uniform_int_distribution<std::size_t>(0, members.size() - 1)(rng)]));
  while (static_cast<int>(centres.size()) < k) {
    double total = 0;
    for (std::size_t i = 0; i < members.size(); ++i) {
      const double d = hamming(centres.back(), members[i]);
      nearest[i] = std::min(nearest[i], d * d);
      total += nearest[i];
    }
    if (total <= 0) break;  // fewer distinct descriptors than k
    double pick = std::uniform_real_distribution<double>(0.0, total)(rng);
    std::size_t chosen = members.size() - 1;
    for (std::size_t i = 0; i < members.size(); ++i) {
      pick -= nearest[i];
      if (pick <= 0) {
        chosen = i;
        break;
      }
    }
    centres.push_back(to_descriptor(members[chosen]));
  }
  std::vector<int> assignment(members.size(), -1);
  for (int it = 0; it < std::max(1, iterations); ++it) {
    bool changed = false;
    for (std::size_t i = 0; i < members.size(); ++i) {
      int best = 0, best_d = std::numeric_limits<int>::max();
      for (int c = 0; c < static_cast<int>(centres.size()); ++c) {
        const int d = hamming(centres[c], members[i]);
        if (d < best_d) {
          best_d = d;
          best = c;
        }
      }
      changed = changed || assignment[i] != best;
      assignment[i] = best;
    }
    groups.assign(centres.size(), {});
    for (std::size_t i = 0; i < members.size(); ++i) groups[assignment[i]].push_back(members[i]);
    if (!changed && it > 0) break;
    for (std::size_t c = 0; c < centres.size(); ++c)
      if (!groups[c].empty()) centres[c] = majority(groups[c]);
  }
  // Drop empty clusters.
  std::size_t out = 0;
  for (std::size_t c = 0; c < centres.size(); ++c) {
    if (groups[c].empty()) continue;
    if (out != c) {  // (a self-move would empty the group)
      centres[out] = centres[c];
      groups[out] = std::move(groups[c]);
    }
    ++out;
  }
  centres.resize(out);
  groups.resize(out);
}

}  // namespace

int hamming(const Descriptor& a, const std::uint8_t* b) {
  int d = 0;
  for (int i = 0; i < 32; i += 8) {
    std::uint64_t x, y;
    std::memcpy(&x, a.data() + i, 8);
    std::memcpy(&y, b + i, 8);
    d += __builtin_popcountll(x ^ y);
  }
  return d;
}

double l1_score(const BowVector& a, const BowVector& b) {
  // For non-negative L1-normalised vectors 1 - |a - b|_1 / 2 = sum over common words of min.
  double s = 0;
  auto i = a.begin(), j = b.begin();
  while (i != a.end() && j != b.end()) {
    if (i->first < j->first) {
      ++i;
    } else if (j->first < i->first) {
      ++j;
    } else {
      s += std::min(i->second, j->second);
      ++i;
      ++j;
    }
  }
  return s;
}

Vocabulary::Vocabulary(int k, int L, int scoring_code, int weighting_code,
                       std::vector<VocabularyNode> nodes)
    : branching(k), depth(L), scoring(scoring_code), weighting(weighting_code),
      nodes_(std::move(nodes)) {
  if (nodes_.empty() || nodes_[0].parent != -1)
    throw std::invalid_argument("vocabulary: node 0 must be the root");
  children_.assign(nodes_.size(), {});
  for (std::size_t i = 1; i < nodes_.size(); ++i) {
    const int p = nodes_[i].parent;
    if (p < 0 || p >= static_cast<int>(i))
      throw std::invalid_argument("vocabulary: node " + std::to_string(i) +
                                  " has no earlier parent");
    if (nodes_[p].word >= 0)
      throw std::invalid_argument("vocabulary: node " + std::to_string(i) + "'s parent is a word");
    children_[p].push_back(static_cast<int>(i));
  }
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    if (nodes_[i].word >= 0) {
      if (!children_[i].empty())
        throw std::invalid_argument("vocabulary: word node " + std::to_string(i) + " has children");
      nodes_[i].word = static_cast<int>(word_nodes_.size());
      word_nodes_.push_back(static_cast<int>(i));
    }
  }
}

int Vocabulary::word_of(const std::uint8_t* d) const {
  int node = 0;
  while (!children_[node].empty()) {
    int best = children_[node].front(), best_d = std::numeric_limits<int>::max();
    for (int c : children_[node]) {
      const int h = hamming(nodes_[c].descriptor, d);
      if (h < best_d) {
        best_d = h;
        best = c;
      }
    }
    node = best;
  }
  return nodes_[node].word;
}

BowVector Vocabulary::transform(const cv::Mat& descriptors) const {
  if (scoring != 0 || weighting != 0)
    throw std::invalid_argument("vocabulary: only L1 scoring with TF-IDF weights is supported");
  if (!descriptors.empty() && (descriptors.type() != CV_8U || descriptors.cols != 32))
    throw std::invalid_argument("vocabulary: descriptors must be Nx32 CV_8U");
  std::vector<std::pair<int, float>> hits;
  hits.reserve(static_cast<std::size_t>(descriptors.rows));
  for (int r = 0; r < descriptors.rows; ++r) {
    const int w = word_of(descriptors.ptr<std::uint8_t>(r));
    if (w >= 0) hits.emplace_back(w, nodes_[word_nodes_[w]].weight);
  }
  std::sort(hits.begin(), hits.end());
  BowVector v;
  double total = 0;
  for (const auto& [w, weight] : hits) {
    if (weight <= 0) continue;  // a word in every training image carries no information
    if (!v.empty() && v.back().first == w) {
      v.back().second += weight;
    } else {
      v.emplace_back(w, weight);
    }
    total += weight;
  }
  if (total > 0)
    for (auto& e : v) e.second = static_cast<float>(e.second / total);
  return v;
}

Vocabulary train_vocabulary(const std::vector<cv::Mat>& images, const VocabularyConfig& c) {
  if (c.branching < 2 || c.depth < 1)
    throw std::invalid_argument("vocabulary: branching >= 2 and depth >= 1");
  std::vector<const std::uint8_t*> all;
  for (const cv::Mat& m : images) {
    if (m.empty()) continue;
    if (m.type() != CV_8U || m.cols != 32)
      throw std::invalid_argument("vocabulary: descriptors must be Nx32 CV_8U");
    for (int r = 0; r < m.rows; ++r) all.push_back(m.ptr<std::uint8_t>(r));
  }
  if (all.empty()) throw std::invalid_argument("vocabulary: no training descriptors");
  std::mt19937 rng(c.seed);
  std::vector<VocabularyNode> nodes(1);
  // Breadth-first: (node, its members, its level).
  struct Pending {
    int node;
    std::vector<const std::uint8_t*> members;
    int level;
  };
  std::vector<Pending> queue;
  queue.push_back({0, std::move(all), 0});
  for (std::size_t q = 0; q < queue.size(); ++q) {
    Pending p = std::move(queue[q]);
    std::vector<Descriptor> centres;
    std::vector<std::vector<const std::uint8_t*>> groups;
    cluster(p.members, c.branching, c.iterations, rng, centres, groups);
    for (std::size_t i = 0; i < centres.size(); ++i) {
      VocabularyNode n;
      n.parent = p.node;
      n.descriptor = centres[i];
      const int id = static_cast<int>(nodes.size());
      const bool leaf = p.level + 1 >= c.depth || groups[i].size() <= 1;
      n.word = leaf ? 0 : -1;  // numbered by the constructor
      nodes.push_back(n);
      if (!leaf) queue.push_back({id, std::move(groups[i]), p.level + 1});
    }
  }
  Vocabulary tmp(c.branching, c.depth, 0, 0, nodes);
  // IDF: log(N / n_w) over the training images.
  std::vector<int> images_with(tmp.words(), 0);
  int n_images = 0;
  for (const cv::Mat& m : images) {
    if (m.empty()) continue;
    ++n_images;
    std::vector<int> seen;
    for (int r = 0; r < m.rows; ++r) seen.push_back(tmp.word_of(m.ptr<std::uint8_t>(r)));
    std::sort(seen.begin(), seen.end());
    seen.erase(std::unique(seen.begin(), seen.end()), seen.end());
    for (int w : seen) ++images_with[w];
  }
  std::vector<VocabularyNode> weighted = tmp.nodes();
  for (VocabularyNode& n : weighted) {
    if (n.word < 0) continue;
    const int k = images_with[n.word];
    n.weight = k > 0 ? static_cast<float>(std::log(static_cast<double>(n_images) / k)) : 0.f;
  }
  return Vocabulary(c.branching, c.depth, 0, 0, std::move(weighted));
}

}  // namespace loopscan::baselines
