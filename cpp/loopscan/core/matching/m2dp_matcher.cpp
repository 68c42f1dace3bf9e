// M2DP rows: the 4 x 4 version dot products of one query against a chunk of database places at
// once (one place per lane), for both halves.
#include "loopscan/core/matching/place_matcher.hpp"
#include "loopscan/core/simd.hpp"

namespace loopscan {
namespace {

constexpr int kVersions = 4;

// db: [version][dim] chunks; q: [version][dim]; best: max dot per lane.
template <typename T, int W>
LOOPSCAN_INLINE void m2dp_best_dot(const T* q, const T* db, int dims, T* best) {
  using V = typename simd::Vec<T, W>::type;
  constexpr int kV = simd::Vec<T, W>::kLanes, kL = simd::kChunkLanes<T>;
  for (int h = 0; h < kL / kV; ++h) {
    V acc[kVersions * kVersions] = {};
    for (int d = 0; d < dims; ++d) {
      V dv[kVersions];
      for (int v = 0; v < kVersions; ++v) {
        dv[v] = simd::load<V>(db + (static_cast<std::size_t>(v) * dims + d) * kL + h * kV);
      }
      for (int qv = 0; qv < kVersions; ++qv) {
        const T x = q[qv * dims + d];
        for (int v = 0; v < kVersions; ++v) acc[qv * kVersions + v] += x * dv[v];
      }
    }
    V b = acc[0];
    for (int i = 1; i < kVersions * kVersions; ++i) b = b > acc[i] ? b : acc[i];
    simd::store(best + h * kV, b);
  }
}

template <typename T>
void kernel_base(const T* q, const T* db, int dims, T* best) {
  m2dp_best_dot<T, 16>(q, db, dims, best);
}

template <typename T>
LOOPSCAN_AVX2 void kernel_avx2(const T* q, const T* db, int dims, T* best) {
  m2dp_best_dot<T, 32>(q, db, dims, best);
}

template <typename T>
class M2dpMatcher final : public PlaceMatcher {
  static constexpr int kL = simd::kChunkLanes<T>;

 public:
  M2dpMatcher() : kernel_(simd::has_avx2() ? kernel_avx2<T> : kernel_base<T>) {}

  void add(const Signature& place) override {
    if (n_ == 0) half_ = static_cast<int>(place.cols() / 2);
    if (n_ % kL == 0) blocks_.resize(blocks_.size() + block_size(), T(0));
    T* block = &blocks_[(n_ / kL) * block_size()];
    const int lane = static_cast<int>(n_ % kL);
    for (int c = 0; c < 2; ++c) {
      for (int v = 0; v < kVersions; ++v) {
        for (int d = 0; d < half_; ++d) {
          block[((c * kVersions + v) * half_ + d) * kL + lane] =
              static_cast<T>(place(v, c * half_ + d));
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
    alignas(32) T best[kL];
    for (int c = 0; c < 2; ++c) {
      for (int v = 0; v < kVersions; ++v) {
        for (int d = 0; d < half_; ++d) q[v * half_ + d] = static_cast<T>(query(v, c * half_ + d));
      }
      for (std::size_t b = 0; b * kL < n_; ++b) {
        kernel_(q.data(), &blocks_[b * block_size() + c * kVersions * half_ * kL], half_, best);
        for (int lane = 0; lane < kL && b * kL + lane < n_; ++lane) {
          rows(c, static_cast<Eigen::Index>(b * kL + lane)) = (1.0 - double(best[lane])) / 2.0;
        }
      }
    }
  }

 private:
  std::size_t block_size() const { return static_cast<std::size_t>(2 * kVersions * half_ * kL); }

  int half_ = 0;
  std::size_t n_ = 0;
  void (*kernel_)(const T*, const T*, int, T*);
  std::vector<T> blocks_;  // per block of kL places: [component][version][dim] chunks
};

}  // namespace

std::unique_ptr<PlaceMatcher> make_m2dp_matcher(Precision precision) {
  if (precision == Precision::Float) return std::make_unique<M2dpMatcher<float>>();
  return std::make_unique<M2dpMatcher<double>>();
}

}  // namespace loopscan
