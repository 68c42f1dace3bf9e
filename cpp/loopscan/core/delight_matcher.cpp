// DELIGHT rows. Where only one histogram has counts, 2 (a - b)^2 / (a + b) is simply 2 (a + b),
// so the chi-square sum of a pair is 2 (sum A + sum B) - sum over shared bins of 8 a b / (a + b),
// and the bins used are nnz(A) + nnz(B) - shared: one pass over the bins per region mask.
#include <algorithm>

#include "loopscan/core/pair_distance.hpp"
#include "loopscan/core/place_matcher.hpp"
#include "loopscan/core/simd.hpp"

namespace loopscan {
namespace {

template <typename T>
class DelightMatcher final : public PlaceMatcher {
  using Vec = typename simd::Lanes<T>::Vec;
  static constexpr int kLanes = simd::Lanes<T>::kCount;
  static constexpr int kRegions = 16;

  struct Totals {
    double sum = 0;
    double nonzero = 0;
  };

 public:
  void add(const Signature& place) override {
    if (n_ == 0) vecs_per_row_ = static_cast<int>((place.cols() + kLanes - 1) / kLanes);
    hist_.resize(hist_.size() + kRegions * vecs_per_row_, Vec{});
    totals_.push_back(pack(place, &hist_[n_ * kRegions * vecs_per_row_]));
    ++n_;
  }

  std::size_t size() const override { return n_; }
  int components() const override { return 1; }

  void distances(const Signature& query, Eigen::MatrixXd& rows) const override {
    rows.resize(1, static_cast<Eigen::Index>(n_));
    std::vector<Vec> q(kRegions * vecs_per_row_);
    const Totals tq = pack(query, q.data());
    const int V = vecs_per_row_;
    for (std::size_t j = 0; j < n_; ++j) {
      const Vec* d = &hist_[j * kRegions * V];
      double best = std::numeric_limits<double>::infinity();
      for (int mask : kDelightRegionMasks) {
        Vec shared{}, overlap{};
        for (int r = 0; r < kRegions; ++r) {
          const Vec* a = &q[r * V];
          const Vec* b = &d[(r ^ mask) * V];
          for (int i = 0; i < V; ++i) {
            const Vec ab = a[i] * b[i];
            const Vec s = a[i] + b[i];
            shared += ab / (s > T(0) ? s : Vec{} + T(1));  // ab = 0 wherever s = 0
            overlap += ab > T(0) ? Vec{} + T(1) : Vec{};
          }
        }
        double h = 0, o = 0;
        for (int lane = 0; lane < kLanes; ++lane) {
          h += shared[lane];
          o += overlap[lane];
        }
        const double used = tq.nonzero + totals_[j].nonzero - o;
        const double sum = 2.0 * (tq.sum + totals_[j].sum) - 8.0 * h;
        best = std::min(best, used > 0 ? sum / used : 0.0);
      }
      rows(0, static_cast<Eigen::Index>(j)) = best;
    }
  }

 private:
  Totals pack(const Signature& place, Vec* out) const {
    Totals t;
    for (int r = 0; r < kRegions; ++r) {
      for (Eigen::Index bin = 0; bin < place.cols(); ++bin) {
        const double v = place(r, bin);
        out[r * vecs_per_row_ + bin / kLanes][bin % kLanes] = static_cast<T>(v);
        t.sum += v;
        t.nonzero += v > 0;
      }
    }
    return t;
  }

  int vecs_per_row_ = 0;
  std::size_t n_ = 0;
  std::vector<Vec> hist_;  // per place: [region][bin / kLanes] -> lanes = bins
  std::vector<Totals> totals_;
};

}  // namespace

std::unique_ptr<PlaceMatcher> make_delight_matcher(Precision precision) {
  if (precision == Precision::Float) return std::make_unique<DelightMatcher<float>>();
  return std::make_unique<DelightMatcher<double>>();
}

std::unique_ptr<PlaceMatcher> make_matcher(Method method, Precision precision,
                                           const ScanContextConfig& sc) {
  switch (method) {
    case Method::ScanContext: return make_scan_context_matcher(precision, sc);
    case Method::M2dp: return make_m2dp_matcher(precision);
    case Method::Delight: return make_delight_matcher(precision);
  }
  return nullptr;
}

}  // namespace loopscan
