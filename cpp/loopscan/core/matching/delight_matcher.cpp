// DELIGHT rows. Where only one histogram has counts, 2 (a - b)^2 / (a + b) is simply 2 (a + b),
// so the chi-square sum of a pair is 2 (sum A + sum B) - sum over shared bins of 8 a b / (a + b),
// and the bins used are nnz(A) + nnz(B) - shared: one pass over the bins per region mask.
#include <algorithm>
#include <limits>

#include "loopscan/core/matching/delight_packed.hpp"
#include "loopscan/core/matching/pair_distance.hpp"
#include "loopscan/core/matching/place_matcher.hpp"
#include "loopscan/core/simd.hpp"

#if defined(__x86_64__)
#include <immintrin.h>
#endif

namespace loopscan {
namespace {

constexpr int kRegions = kDelightRegions;

// Sums of a b / (a + b) and of [a b > 0] over the bins of the 16 region pairs (r, r ^ mask),
// for the four masks. a, b: [region][bin] with `bins` a multiple of the chunk.
// The double-precision kernel (reference evaluation) divides.
template <int W>
LOOPSCAN_INLINE void delight_shared_double(const double* a, const double* b, int bins,
                                           double* shared, double* overlap) {
  using V = typename simd::Vec<double, W>::type;
  constexpr int kV = simd::Vec<double, W>::kLanes;
  for (int m = 0; m < 4; ++m) {
    const int mask = kDelightRegionMasks[m];
    V sh{}, ov{};
    for (int r = 0; r < kRegions; ++r) {
      const double* ar = a + static_cast<std::size_t>(r) * bins;
      const double* br = b + static_cast<std::size_t>(r ^ mask) * bins;
      for (int i = 0; i < bins; i += kV) {
        const V x = simd::load<V>(ar + i), y = simd::load<V>(br + i);
        const V xy = x * y, s = x + y;
        sh += xy / (s > 0.0 ? s : V{} + 1.0);  // xy = 0 wherever s = 0
        ov += xy > 0.0 ? V{} + 1.0 : V{};
      }
    }
    shared[m] = overlap[m] = 0;
    for (int l = 0; l < kV; ++l) {
      shared[m] += sh[l];
      overlap[m] += ov[l];
    }
  }
}

void kernel_base(const double* a, const double* b, int bins, double* shared, double* overlap) {
  delight_shared_double<16>(a, b, bins, shared, overlap);
}

LOOPSCAN_AVX2 void kernel_avx2(const double* a, const double* b, int bins, double* shared,
                               double* overlap) {
  delight_shared_double<32>(a, b, bins, shared, overlap);
}

// The float kernels multiply by the approximate-reciprocal instruction refined by one Newton
// step (relative error ~1e-7) instead of dividing: the divider's throughput was the limit.
#if defined(__x86_64__)
void kernel_base(const float* a, const float* b, int bins, double* shared, double* overlap) {
  const __m128 one = _mm_set1_ps(1.f), two = _mm_set1_ps(2.f), zero = _mm_setzero_ps();
  for (int m = 0; m < 4; ++m) {
    const int mask = kDelightRegionMasks[m];
    __m128 sh = _mm_setzero_ps(), ov = _mm_setzero_ps();
    for (int r = 0; r < kRegions; ++r) {
      const float* ar = a + static_cast<std::size_t>(r) * bins;
      const float* br = b + static_cast<std::size_t>(r ^ mask) * bins;
      for (int i = 0; i < bins; i += 4) {
        const __m128 x = _mm_loadu_ps(ar + i), y = _mm_loadu_ps(br + i);
        const __m128 xy = _mm_mul_ps(x, y), s = _mm_max_ps(_mm_add_ps(x, y), one);
        __m128 inv = _mm_rcp_ps(s);
        inv = _mm_mul_ps(inv, _mm_sub_ps(two, _mm_mul_ps(s, inv)));
        sh = _mm_add_ps(sh, _mm_mul_ps(xy, inv));
        ov = _mm_add_ps(ov, _mm_and_ps(_mm_cmpgt_ps(xy, zero), one));
      }
    }
    alignas(16) float h[4], o[4];
    _mm_store_ps(h, sh);
    _mm_store_ps(o, ov);
    shared[m] = double(h[0]) + h[1] + h[2] + h[3];
    overlap[m] = double(o[0]) + o[1] + o[2] + o[3];
  }
}

LOOPSCAN_AVX2 void kernel_avx2(const float* a, const float* b, int bins, double* shared,
                               double* overlap) {
  const __m256 one = _mm256_set1_ps(1.f), two = _mm256_set1_ps(2.f);
  const __m256 zero = _mm256_setzero_ps();
  for (int m = 0; m < 4; ++m) {
    const int mask = kDelightRegionMasks[m];
    __m256 sh = _mm256_setzero_ps(), ov = _mm256_setzero_ps();
    for (int r = 0; r < kRegions; ++r) {
      const float* ar = a + static_cast<std::size_t>(r) * bins;
      const float* br = b + static_cast<std::size_t>(r ^ mask) * bins;
      for (int i = 0; i < bins; i += 8) {
        const __m256 x = _mm256_loadu_ps(ar + i), y = _mm256_loadu_ps(br + i);
        const __m256 xy = _mm256_mul_ps(x, y), s = _mm256_max_ps(_mm256_add_ps(x, y), one);
        __m256 inv = _mm256_rcp_ps(s);
        inv = _mm256_mul_ps(inv, _mm256_fnmadd_ps(s, inv, two));
        sh = _mm256_fmadd_ps(xy, inv, sh);
        ov = _mm256_add_ps(ov, _mm256_and_ps(_mm256_cmp_ps(xy, zero, _CMP_GT_OQ), one));
      }
    }
    alignas(32) float h[8], o[8];
    _mm256_store_ps(h, sh);
    _mm256_store_ps(o, ov);
    shared[m] = overlap[m] = 0;
    for (int l = 0; l < 8; ++l) {
      shared[m] += h[l];
      overlap[m] += o[l];
    }
  }
}
#else
void kernel_base(const float* a, const float* b, int bins, double* shared, double* overlap) {
  for (int m = 0; m < 4; ++m) {
    shared[m] = overlap[m] = 0;
    for (int r = 0; r < kRegions; ++r) {
      for (int i = 0; i < bins; ++i) {
        const double x = a[r * bins + i], y = b[(r ^ kDelightRegionMasks[m]) * bins + i];
        if (x > 0 && y > 0) {
          shared[m] += x * y / (x + y);
          overlap[m] += 1;
        }
      }
    }
  }
}
void kernel_avx2(const float* a, const float* b, int bins, double* shared, double* overlap) {
  kernel_base(a, b, bins, shared, overlap);
}
#endif

// Distance from the shared sums of the four region masks (see the top of the file).
double distance_from_shared(const DelightTotals& ta, const DelightTotals& tb, const double* shared,
                            const double* overlap) {
  double best = std::numeric_limits<double>::infinity();
  for (int m = 0; m < 4; ++m) {
    const double used = ta.nonzero + tb.nonzero - overlap[m];
    const double sum = 2.0 * (ta.sum + tb.sum) - 8.0 * shared[m];
    best = std::min(best, used > 0 ? sum / used : 0.0);
  }
  return best;
}

template <typename T>
DelightTotals pack_histograms(const Signature& place, int bins, T* out) {
  DelightTotals t;
  for (int r = 0; r < kRegions; ++r) {
    for (Eigen::Index bin = 0; bin < place.cols(); ++bin) {
      const double v = place(r, bin);
      out[r * bins + bin] = static_cast<T>(v);
      t.sum += v;
      t.nonzero += v > 0;
    }
  }
  return t;
}

template <typename T>
class DelightMatcher final : public PlaceMatcher {
  using Totals = DelightTotals;

 public:
  DelightMatcher() {
    void (*base)(const T*, const T*, int, double*, double*) = kernel_base;
    void (*avx2)(const T*, const T*, int, double*, double*) = kernel_avx2;
    kernel_ = simd::has_avx2() ? avx2 : base;
  }

  void add(const Signature& place) override {
    if (n_ == 0) {
      const int kL = simd::kChunkLanes<T>;
      bins_ = static_cast<int>((place.cols() + kL - 1) / kL * kL);  // 8 for float
    }
    hist_.resize(hist_.size() + static_cast<std::size_t>(kRegions) * bins_, T(0));
    totals_.push_back(pack(place, &hist_[n_ * kRegions * bins_]));
    ++n_;
  }

  std::size_t size() const override { return n_; }
  int components() const override { return 1; }

  void distances(const Signature& query, Eigen::MatrixXd& rows) const override {
    rows.resize(1, static_cast<Eigen::Index>(n_));
    std::vector<T> q(static_cast<std::size_t>(kRegions) * bins_, T(0));
    const Totals tq = pack(query, q.data());
    double shared[4], overlap[4];
    for (std::size_t j = 0; j < n_; ++j) {
      kernel_(q.data(), &hist_[j * kRegions * bins_], bins_, shared, overlap);
      rows(0, static_cast<Eigen::Index>(j)) = distance_from_shared(tq, totals_[j], shared, overlap);
    }
  }

 private:
  Totals pack(const Signature& place, T* out) const { return pack_histograms(place, bins_, out); }

  int bins_ = 0;
  std::size_t n_ = 0;
  void (*kernel_)(const T*, const T*, int, double*, double*);
  std::vector<T> hist_;  // per place: [region][bin]
  std::vector<Totals> totals_;
};

}  // namespace

int delight_padded_bins(int columns) { return (columns + 7) / 8 * 8; }

DelightTotals delight_pack(const Signature& place, int padded_bins, float* out) {
  std::fill(out, out + static_cast<std::size_t>(kRegions) * padded_bins, 0.f);
  return pack_histograms(place, padded_bins, out);
}

double delight_packed_distance(const float* a, const DelightTotals& ta, const float* b,
                               const DelightTotals& tb, int padded_bins) {
  static const auto kernel =
      simd::has_avx2()
          ? static_cast<void (*)(const float*, const float*, int, double*, double*)>(kernel_avx2)
          : static_cast<void (*)(const float*, const float*, int, double*, double*)>(kernel_base);
  double shared[4], overlap[4];
  kernel(a, b, padded_bins, shared, overlap);
  return distance_from_shared(ta, tb, shared, overlap);
}

std::unique_ptr<PlaceMatcher> make_delight_matcher(Precision precision) {
  if (precision == Precision::Float) return std::make_unique<DelightMatcher<float>>();
  return std::make_unique<DelightMatcher<double>>();
}

std::unique_ptr<PlaceMatcher> make_matcher(Method method, Precision precision,
                                           const ScanContextConfig& sc) {
  switch (method) {
    case Method::ScanContext:
      return make_scan_context_matcher(precision, sc);
    case Method::M2dp:
      return make_m2dp_matcher(precision);
    case Method::Delight:
      return make_delight_matcher(precision);
    case Method::BirdsEye:
      return make_birds_eye_matcher();
  }
  return nullptr;
}

}  // namespace loopscan
