// Scan Context rows through the correlation theorem: the best dot product over all sector
// shifts (and over the mirrored sector order: a convolution) is read from an inverse DFT of a
// single ring-summed cross spectrum, so a pair costs O(R S + S^2 / 2) instead of O(R S^2).
// A signature with several rows (ScanContextConfig::lateral_versions_m) is stored by its first
// row and queried with all: per half, the smallest distance over the rows.
// Double precision (reference mode): database places interleaved, one per vector lane. Float:
// the place database's packed-spectra pair kernel (scan_context_spectra.hpp).
#include <algorithm>
#include <cmath>
#include <limits>

#include "loopscan/core/matching/place_matcher.hpp"
#include "loopscan/core/matching/scan_context_spectra.hpp"
#include "loopscan/core/simd.hpp"

namespace loopscan {
namespace {

// The interleaved kernel: for one query spectrum and one block of database places (one place
// per lane), the best dot product over all sector shifts, of the correlation and of the
// mirrored-order convolution, read from an inverse real DFT of the ring-summed spectra.
struct ScanContextKernelArgs {
  int rings, bins, sectors;  // bins = sectors / 2 + 1
  const void* inv_cos;       // (sectors/2 + 1) x bins, weights and 1/S folded in
  const void* inv_sin;
};

// block: [ring][bin] {re chunk, im chunk}; q: [ring][bin] re and im; best: one chunk.
template <typename T, int W>
LOOPSCAN_INLINE void scan_context_best_dot(const ScanContextKernelArgs& a, const T* qre,
                                           const T* qim, const T* block, T* best) {
  using V = typename simd::Vec<T, W>::type;
  constexpr int kV = simd::Vec<T, W>::kLanes, kL = simd::kChunkLanes<T>;
  constexpr int kMaxBins = 64;
  const int R = a.rings, K = std::min(a.bins, kMaxBins), S = a.sectors;
  const T* ic = static_cast<const T*>(a.inv_cos);
  const T* is = static_cast<const T*>(a.inv_sin);
  for (int h = 0; h < kL / kV; ++h) {
    V X[kMaxBins], Y[kMaxBins], Z[kMaxBins], U[kMaxBins];
    for (int k = 0; k < K; ++k) X[k] = Y[k] = Z[k] = U[k] = V{};
    for (int r = 0; r < R; ++r) {
      const T* d = block + static_cast<std::size_t>(r) * K * 2 * kL + h * kV;
      const T* qr = qre + r * K;
      const T* qi = qim + r * K;
      for (int k = 0; k < K; ++k) {
        const V dre = simd::load<V>(d + 2 * k * kL), dim = simd::load<V>(d + (2 * k + 1) * kL);
        X[k] += qr[k] * dre;  // sum Qre Dre
        Y[k] += qi[k] * dim;  // sum Qim Dim
        Z[k] += qi[k] * dre;  // sum Qim Dre
        U[k] += qr[k] * dim;  // sum Qre Dim
      }
    }
    // Correlation spectrum Q conj(D) = (X + Y, Z - U); convolution Q D = (X - Y, Z + U).
    for (int k = 0; k < K; ++k) {
      const V x = X[k], y = Y[k], z = Z[k], u = U[k];
      X[k] = x + y;
      Y[k] = x - y;
      Z[k] = z - u;
      U[k] = z + u;
    }
    V b = V{} - T(2);
    for (int m = 0; m <= S / 2; ++m) {
      const T* cm = ic + m * K;
      const T* sm = is + m * K;
      V ac{}, bc{}, av{}, bv{};
      for (int k = 0; k < K; ++k) {
        ac += cm[k] * X[k];
        av += cm[k] * Y[k];
        bc += sm[k] * Z[k];
        bv += sm[k] * U[k];
      }
      // Shifts m and S - m: A + B and A - B, so the larger is A + |B|.
      const V corr = ac + (bc < 0 ? -bc : bc), conv = av + (bv < 0 ? -bv : bv);
      b = b > corr ? b : corr;
      b = b > conv ? b : conv;
    }
    simd::store(best + h * kV, b);
  }
}

template <typename T>
void kernel_base(const ScanContextKernelArgs& a, const T* qre, const T* qim, const T* block,
                 T* best) {
  scan_context_best_dot<T, 16>(a, qre, qim, block, best);
}

template <typename T>
LOOPSCAN_AVX2 void kernel_avx2(const ScanContextKernelArgs& a, const T* qre, const T* qim,
                               const T* block, T* best) {
  scan_context_best_dot<T, 32>(a, qre, qim, block, best);
}

template <typename T>
class ScanContextMatcher final : public PlaceMatcher {
  static constexpr int kL = simd::kChunkLanes<T>;

 public:
  explicit ScanContextMatcher(const ScanContextConfig& c)
      : rings_(c.rings), sectors_(c.sectors), bins_(c.sectors / 2 + 1) {
    const int S = sectors_, K = bins_;
    fwd_cos_.resize(K * S);
    fwd_sin_.resize(K * S);
    for (int k = 0; k < K; ++k) {
      for (int s = 0; s < S; ++s) {
        const double a = 2.0 * M_PI * ((static_cast<long>(k) * s) % S) / S;
        fwd_cos_[k * S + s] = std::cos(a);
        fwd_sin_[k * S + s] = -std::sin(a);
      }
    }
    // c_m = sum_k w_k (Re P_k cos(2 pi k m / S) - Im P_k sin(...)) / S, w = 1 at k = 0, S/2.
    inv_cos_.resize((S / 2 + 1) * K);
    inv_sin_.resize((S / 2 + 1) * K);
    for (int m = 0; m <= S / 2; ++m) {
      for (int k = 0; k < K; ++k) {
        const double w = (k == 0 || 2 * k == S) ? 1.0 : 2.0;
        const double a = 2.0 * M_PI * ((static_cast<long>(k) * m) % S) / S;
        inv_cos_[m * K + k] = static_cast<T>(w * std::cos(a) / S);
        inv_sin_[m * K + k] = static_cast<T>(-w * std::sin(a) / S);
      }
    }
    args_ = {rings_, bins_, sectors_, inv_cos_.data(), inv_sin_.data()};
    kernel_ = simd::has_avx2() ? kernel_avx2<T> : kernel_base<T>;
  }

  void add(const Signature& signature) override {
    const Signature place = signature.topRows(1);  // the place; other rows are query versions
    if (n_ % kL == 0) blocks_.resize(blocks_.size() + block_size(), T(0));
    T* block = &blocks_[(n_ / kL) * block_size()];
    const int lane = static_cast<int>(n_ % kL);
    std::vector<T> re, im;
    for (int c = 0; c < 2; ++c) {
      spectrum(place, c, re, im);
      T* part = block + static_cast<std::size_t>(c) * rings_ * bins_ * 2 * kL;
      for (int i = 0; i < rings_ * bins_; ++i) {
        part[(2 * i) * kL + lane] = re[i];
        part[(2 * i + 1) * kL + lane] = im[i];
      }
    }
    ++n_;
  }

  std::size_t size() const override { return n_; }
  int components() const override { return 2; }

  void distances(const Signature& query, Eigen::MatrixXd& rows) const override {
    rows.setConstant(2, static_cast<Eigen::Index>(n_), std::numeric_limits<double>::infinity());
    std::vector<T> qre, qim;
    alignas(32) T best[kL];
    for (Eigen::Index v = 0; v < query.rows(); ++v) {  // each version: the smallest distance
      const Signature version = query.row(v);
      for (int c = 0; c < 2; ++c) {
        spectrum(version, c, qre, qim);
        for (std::size_t b = 0; b * kL < n_; ++b) {
          const T* part =
              &blocks_[b * block_size() + static_cast<std::size_t>(c) * rings_ * bins_ * 2 * kL];
          kernel_(args_, qre.data(), qim.data(), part, best);
          for (int lane = 0; lane < kL && b * kL + lane < n_; ++lane) {
            double& d = rows(c, static_cast<Eigen::Index>(b * kL + lane));
            d = std::min(d, (1.0 - double(best[lane])) / 2.0);
          }
        }
      }
    }
  }

 private:
  std::size_t block_size() const { return static_cast<std::size_t>(2 * rings_ * bins_ * 2 * kL); }

  // DFT along sectors of each ring of one L2-normalised half (a zero half stays zero).
  void spectrum(const Signature& place, int c, std::vector<T>& re, std::vector<T>& im) const {
    const int R = rings_, S = sectors_, K = bins_;
    const Eigen::Index stride = place.rows();
    const double* x = place.data() + static_cast<Eigen::Index>(c) * R * S * stride;
    double norm2 = 0;
    for (int i = 0; i < R * S; ++i) norm2 += x[i * stride] * x[i * stride];
    const double scale = norm2 > 0 ? 1.0 / std::sqrt(norm2) : 0.0;
    re.assign(R * K, T(0));
    im.assign(R * K, T(0));
    std::vector<double> ring(S);
    for (int r = 0; r < R; ++r) {
      bool any = false;
      for (int s = 0; s < S; ++s) {
        ring[s] = x[(s * R + r) * stride] * scale;
        any = any || ring[s] != 0.0;
      }
      if (!any) continue;
      for (int k = 0; k < K; ++k) {
        double sr = 0, si = 0;
        for (int s = 0; s < S; ++s) {
          sr += ring[s] * fwd_cos_[k * S + s];
          si += ring[s] * fwd_sin_[k * S + s];
        }
        re[r * K + k] = static_cast<T>(sr);
        im[r * K + k] = static_cast<T>(si);
      }
    }
  }

  int rings_, sectors_, bins_;
  std::size_t n_ = 0;
  std::vector<double> fwd_cos_, fwd_sin_;
  std::vector<T> inv_cos_, inv_sin_;
  ScanContextKernelArgs args_{};
  void (*kernel_)(const ScanContextKernelArgs&, const T*, const T*, const T*, T*) = nullptr;
  std::vector<T> blocks_;  // per block of kL places: [component][ring][bin] {re, im} chunks
};

// Single precision with an even sector count: the place database's packed-spectra pair
// kernel (scan_context_spectra.hpp), one place after the other.
class PackedScanContextMatcher final : public PlaceMatcher {
 public:
  explicit PackedScanContextMatcher(const ScanContextConfig& c)
      : spectra_(c), arena_(static_cast<std::size_t>(spectra_.floats_per_place())) {}

  void add(const Signature& place) override {
    std::vector<float> packed(arena_.floats_per_record());
    spectra_.pack(place.topRows(1), packed.data());
    arena_.append(packed.data());
  }
  std::size_t size() const override { return arena_.size(); }
  int components() const override { return 2; }

  // Version by version over all places: one query stays in L1 while the places stream by
  // (all versions on each place in turn measured no faster on k06's 880 places).
  void distances(const Signature& query, Eigen::MatrixXd& rows) const override {
    rows.setConstant(2, static_cast<Eigen::Index>(arena_.size()),
                     std::numeric_limits<double>::infinity());
    float best[2];
    for (const ScanContextSpectra::Query& q : spectra_.prepare_versions(query)) {
      for (std::size_t j = 0; j < arena_.size(); ++j) {
        spectra_.best_dots(q, arena_.at(j), best);
        for (int c = 0; c < 2; ++c) {
          double& d = rows(c, static_cast<Eigen::Index>(j));
          d = std::min(d, (1.0 - double(best[c])) / 2.0);
        }
      }
    }
  }

 private:
  ScanContextSpectra spectra_;
  PayloadArena arena_;
};

}  // namespace

std::unique_ptr<PlaceMatcher> make_scan_context_matcher(Precision precision,
                                                        const ScanContextConfig& config) {
  // The packed kernel needs an even sector count; odd counts (unusual) take the double path.
  if (precision == Precision::Float && config.sectors % 2 == 0) {
    return std::make_unique<PackedScanContextMatcher>(config);
  }
  return std::make_unique<ScanContextMatcher<double>>(config);
}

}  // namespace loopscan
