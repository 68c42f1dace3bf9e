// Scan Context rows through the correlation theorem: the best dot product over all sector
// shifts (and over the mirrored sector order: a convolution) is read from an inverse DFT of a
// single ring-summed cross spectrum, so a pair costs O(R S + S^2 / 2) instead of O(R S^2).
#include <cmath>

#include "loopscan/core/place_matcher.hpp"
#include "loopscan/core/simd.hpp"

namespace loopscan {
namespace {

template <typename T>
class ScanContextMatcher final : public PlaceMatcher {
  using Vec = typename simd::Lanes<T>::Vec;
  static constexpr int kLanes = simd::Lanes<T>::kCount;

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
  }

  void add(const Signature& place) override {
    if (n_ % kLanes == 0) blocks_.resize(blocks_.size() + block_size(), Vec{});
    std::vector<T> re, im;
    Vec* block = &blocks_[(n_ / kLanes) * block_size()];
    const int lane = static_cast<int>(n_ % kLanes);
    for (int c = 0; c < 2; ++c) {
      spectrum(place, c, re, im);
      for (int i = 0; i < rings_ * bins_; ++i) {
        block[(c * rings_ * bins_ + i) * 2][lane] = re[i];
        block[(c * rings_ * bins_ + i) * 2 + 1][lane] = im[i];
      }
    }
    ++n_;
  }

  std::size_t size() const override { return n_; }
  int components() const override { return 2; }

  void distances(const Signature& query, Eigen::MatrixXd& rows) const override {
    rows.resize(2, static_cast<Eigen::Index>(n_));
    std::vector<T> qre, qim;
    std::vector<Vec> acc(4 * bins_);
    for (int c = 0; c < 2; ++c) {
      spectrum(query, c, qre, qim);
      for (std::size_t b = 0; b * kLanes < n_; ++b) {
        const Vec* block = &blocks_[b * block_size() + c * rings_ * bins_ * 2];
        const Vec best = best_dot(qre.data(), qim.data(), block, acc.data());
        for (int lane = 0; lane < kLanes && b * kLanes + lane < n_; ++lane) {
          rows(c, static_cast<Eigen::Index>(b * kLanes + lane)) = (1.0 - double(best[lane])) / 2.0;
        }
      }
    }
  }

 private:
  std::size_t block_size() const { return static_cast<std::size_t>(2 * rings_ * bins_ * 2); }

  // DFT along sectors of each ring of one L2-normalised half (zero half stays zero).
  void spectrum(const Signature& place, int c, std::vector<T>& re, std::vector<T>& im) const {
    const int R = rings_, S = sectors_, K = bins_;
    const double* x = place.data() + static_cast<Eigen::Index>(c) * R * S * place.rows();
    double norm2 = 0;
    for (int i = 0; i < R * S; ++i) norm2 += x[i * place.rows()] * x[i * place.rows()];
    const double scale = norm2 > 0 ? 1.0 / std::sqrt(norm2) : 0.0;
    re.assign(R * K, T(0));
    im.assign(R * K, T(0));
    std::vector<double> ring(S);
    for (int r = 0; r < R; ++r) {
      for (int s = 0; s < S; ++s) ring[s] = x[(s * R + r) * place.rows()] * scale;
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

  // Per lane: max over shifts of the correlation and of the convolution.
  Vec best_dot(const T* qre, const T* qim, const Vec* block, Vec* acc) const {
    const int R = rings_, K = bins_, S = sectors_;
    Vec* X = acc;  // sum Qre Dre
    Vec* Y = acc + K;  // sum Qim Dim
    Vec* Z = acc + 2 * K;  // sum Qim Dre
    Vec* W = acc + 3 * K;  // sum Qre Dim
    for (int i = 0; i < 4 * K; ++i) acc[i] = Vec{};
    for (int r = 0; r < R; ++r) {
      const Vec* d = block + r * K * 2;
      const T* qr = qre + r * K;
      const T* qi = qim + r * K;
      for (int k = 0; k < K; ++k) {
        const Vec dre = d[2 * k], dim = d[2 * k + 1];
        X[k] += qr[k] * dre;
        Y[k] += qi[k] * dim;
        Z[k] += qi[k] * dre;
        W[k] += qr[k] * dim;
      }
    }
    Vec best = Vec{} - T(2);
    for (int m = 0; m <= S / 2; ++m) {
      const T* ck = &inv_cos_[m * K];
      const T* sk = &inv_sin_[m * K];
      Vec a_corr{}, b_corr{}, a_conv{}, b_conv{};
      for (int k = 0; k < K; ++k) {
        a_corr += ck[k] * (X[k] + Y[k]);
        b_corr += sk[k] * (Z[k] - W[k]);
        a_conv += ck[k] * (X[k] - Y[k]);
        b_conv += sk[k] * (Z[k] + W[k]);
      }
      const Vec corr = a_corr + (b_corr < 0 ? -b_corr : b_corr);
      const Vec conv = a_conv + (b_conv < 0 ? -b_conv : b_conv);
      best = best > corr ? best : corr;
      best = best > conv ? best : conv;
    }
    return best;
  }

  int rings_, sectors_, bins_;
  std::size_t n_ = 0;
  std::vector<double> fwd_cos_, fwd_sin_;
  std::vector<T> inv_cos_, inv_sin_;
  std::vector<Vec> blocks_;  // per block of kLanes places: [component][ring][bin] {re, im}
};

}  // namespace

std::unique_ptr<PlaceMatcher> make_scan_context_matcher(Precision precision,
                                                        const ScanContextConfig& config) {
  if (precision == Precision::Float) return std::make_unique<ScanContextMatcher<float>>(config);
  return std::make_unique<ScanContextMatcher<double>>(config);
}

}  // namespace loopscan
