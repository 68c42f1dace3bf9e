#include "loopscan/baselines/baseline_matching.hpp"

#include <chrono>
#include <cstdlib>
#include <limits>
#include <stdexcept>

#include "loopscan/baselines/inverted_index.hpp"

namespace loopscan::baselines {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kInf = std::numeric_limits<double>::infinity();

double mean_ms(Clock::time_point t0, std::size_t n) {
  const double ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  return n == 0 ? 0.0 : ms / static_cast<double>(n);
}

}  // namespace

BaselineMatches best_gist_matches(const std::vector<Eigen::VectorXf>& queries,
                                  const std::vector<Eigen::VectorXf>& database, int mask) {
  BaselineMatches out;
  const auto t0 = Clock::now();
  for (std::size_t i = 0; i < queries.size(); ++i) {
    eval::QueryMatch m{static_cast<int>(i), -1, kInf};
    for (std::size_t j = 0; j < database.size(); ++j) {
      if (std::abs(static_cast<long>(i) - static_cast<long>(j)) < mask) continue;
      if (database[j].size() != queries[i].size())
        throw std::invalid_argument("GIST descriptors of different lengths");
      const double d = (queries[i] - database[j]).norm();
      if (d < m.distance) {
        m.distance = d;
        m.match = static_cast<int>(j);
      }
    }
    out.matches.push_back(m);
  }
  out.query_ms = mean_ms(t0, queries.size());
  return out;
}

BaselineMatches best_bow_matches(const std::vector<BowVector>& queries,
                                 const std::vector<BowVector>& database, int mask) {
  BaselineMatches out;
  InvertedIndex index;
  for (const BowVector& v : database) index.add(v);
  const auto t0 = Clock::now();
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const long q = static_cast<long>(i);
    const auto best = index.query(queries[i], 1, [q, mask](int j) { return std::abs(q - j) >= mask; });
    eval::QueryMatch m{static_cast<int>(i), -1, kInf};
    if (!best.empty()) {
      m.match = best.front().image;
      m.distance = 1.0 - best.front().score;
    } else {
      // No shared word with any allowed place: the first allowed one at the largest distance.
      for (std::size_t j = 0; j < database.size(); ++j) {
        if (std::abs(q - static_cast<long>(j)) >= mask) {
          m.match = static_cast<int>(j);
          m.distance = 1.0;
          break;
        }
      }
    }
    out.matches.push_back(m);
  }
  out.query_ms = mean_ms(t0, queries.size());
  return out;
}

}  // namespace loopscan::baselines
