// M2DP rows: the 4 x 4 version dot products of one query against kLanes database places at
// once (one place per lane), for both halves.
#include <algorithm>

#include "loopscan/core/place_matcher.hpp"
#include "loopscan/core/simd.hpp"

namespace loopscan {
namespace {

template <typename T>
class M2dpMatcher final : public PlaceMatcher {
  using Vec = typename simd::Lanes<T>::Vec;
  static constexpr int kLanes = simd::Lanes<T>::kCount;
  static constexpr int kVersions = 4;

 public:
  void add(const Signature& place) override {
    if (n_ == 0) half_ = static_cast<int>(place.cols() / 2);
    if (n_ % kLanes == 0) blocks_.resize(blocks_.size() + block_size(), Vec{});
    Vec* block = &blocks_[(n_ / kLanes) * block_size()];
    const int lane = static_cast<int>(n_ % kLanes);
    for (int c = 0; c < 2; ++c) {
      for (int v = 0; v < kVersions; ++v) {
        for (int d = 0; d < half_; ++d) {
          block[(c * kVersions + v) * half_ + d][lane] = static_cast<T>(place(v, c * half_ + d));
        }
      }
    }
    ++n_;
  }

  std::size_t size() const override { return n_; }
  int components() const override { return 2; }

  void distances(const Signature& query, Eigen::MatrixXd& rows) const override {
    rows.resize(2, static_cast<Eigen::Index>(n_));
    std::vector<T> q(kVersions * half_);
    for (int c = 0; c < 2; ++c) {
      for (int v = 0; v < kVersions; ++v) {
        for (int d = 0; d < half_; ++d) q[v * half_ + d] = static_cast<T>(query(v, c * half_ + d));
      }
      for (std::size_t b = 0; b * kLanes < n_; ++b) {
        const Vec best = best_dot(q.data(), &blocks_[b * block_size() + c * kVersions * half_]);
        for (int lane = 0; lane < kLanes && b * kLanes + lane < n_; ++lane) {
          rows(c, static_cast<Eigen::Index>(b * kLanes + lane)) = (1.0 - double(best[lane])) / 2.0;
        }
      }
    }
  }

 private:
  std::size_t block_size() const { return static_cast<std::size_t>(2 * kVersions * half_); }

  Vec best_dot(const T* q, const Vec* db) const {
    Vec acc[kVersions * kVersions] = {};
    for (int d = 0; d < half_; ++d) {
      const Vec d0 = db[d], d1 = db[half_ + d], d2 = db[2 * half_ + d], d3 = db[3 * half_ + d];
      for (int qv = 0; qv < kVersions; ++qv) {
        const T x = q[qv * half_ + d];
        acc[qv * 4 + 0] += x * d0;
        acc[qv * 4 + 1] += x * d1;
        acc[qv * 4 + 2] += x * d2;
        acc[qv * 4 + 3] += x * d3;
      }
    }
    Vec best = acc[0];
    for (int i = 1; i < kVersions * kVersions; ++i) best = best > acc[i] ? best : acc[i];
    return best;
  }

  int half_ = 0;
  std::size_t n_ = 0;
  std::vector<Vec> blocks_;  // per block: [component][version][dim] -> lanes = places
};

}  // namespace

std::unique_ptr<PlaceMatcher> make_m2dp_matcher(Precision precision) {
  if (precision == Precision::Float) return std::make_unique<M2dpMatcher<float>>();
  return std::make_unique<M2dpMatcher<double>>();
}

}  // namespace loopscan
