#pragma once
// The renderer's sensor noise, written out so it inlines into the pixel loop (the library's
// out-of-line calls were a fifth of a render): exactly the numbers std::normal_distribution
// <double> draws from std::mt19937 in libstdc++ (Marsaglia's polar method on
// generate_canonical<double, 53>), so the images did not change, and with any library.
#include <cmath>
#include <cstdint>

namespace loopscan::sim {

// MT19937 with 32-bit words: the same sequence as std::mt19937 from the same seed.
class Mt19937 {
 public:
  static constexpr std::uint32_t kN = 624;
  explicit Mt19937(std::uint32_t seed) {
    s_[0] = seed;
    for (std::uint32_t i = 1; i < kN; ++i)
      s_[i] = 1812433253U * (s_[i - 1] ^ (s_[i - 1] >> 30)) + i;
  }
  std::uint32_t operator()() {
    if (i_ >= kN) twist();
    return temper(s_[i_++]);
  }
  // The next kN outputs at once (plain loops the compiler vectorises); only at a block start,
  // i.e. before any single draw or right after kN of them.
  void next_block(std::uint32_t* out) {
    twist();
    for (std::uint32_t k = 0; k < kN; ++k) out[k] = temper(s_[k]);
    i_ = kN;
  }

 private:
  static constexpr std::uint32_t kM = 397;
  static std::uint32_t temper(std::uint32_t y) {
    y ^= y >> 11;
    y ^= (y << 7) & 0x9d2c5680U;
    y ^= (y << 15) & 0xefc60000U;
    return y ^ (y >> 18);
  }
  static std::uint32_t step(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    const std::uint32_t y = (a & 0x80000000U) | (b & 0x7fffffffU);
    return c ^ (y >> 1) ^ ((y & 1U) ? 0x9908b0dfU : 0U);
  }
  void twist() {  // three plain sweeps (the compiler vectorises them)
    std::uint32_t k = 0;
    for (; k < kN - kM; ++k) s_[k] = step(s_[k], s_[k + 1], s_[k + kM]);
    for (; k < kN - 1; ++k) s_[k] = step(s_[k], s_[k + 1], s_[k + kM - kN]);
    s_[kN - 1] = step(s_[kN - 1], s_[0], s_[kM - 1]);
    i_ = 0;
  }
  std::uint32_t s_[kN];
  std::uint32_t i_ = kN;
};

// Normal(0, sigma) samples, in libstdc++'s order (pairs, the second of a pair returned first).
// The uniforms are made a generator block at a time (tempering and conversion vectorise); the
// polar method's rejection, logarithm and square root stay scalar, glibc's log.
class GaussianNoise {
 public:
  GaussianNoise(std::uint32_t seed, double sigma) : rng_(seed), sigma_(sigma) {}
  double operator()() {
    if (saved_available_) {
      saved_available_ = false;
      return saved_ * sigma_ + 0.0;
    }
    double x, y, r2;
    do {
      x = 2.0 * uniform() - 1.0;
      y = 2.0 * uniform() - 1.0;
      r2 = x * x + y * y;
    } while (r2 > 1.0 || r2 == 0.0);
    const double mult = std::sqrt(-2.0 * std::log(r2) / r2);
    saved_ = x * mult;
    saved_available_ = true;
    return y * mult * sigma_ + 0.0;
  }

 private:
  static constexpr std::uint32_t kUniforms = Mt19937::kN / 2;
  // generate_canonical<double, 53>: two 32-bit draws, low word first (kN is even: a pair never
  // straddles two blocks).
  double uniform() {
    if (next_ == kUniforms) refill();
    return uniforms_[next_++];
  }
  void refill() {
    std::uint32_t words[Mt19937::kN];
    rng_.next_block(words);
    constexpr double kBelowOne = 0x1.fffffffffffffp-1;  // std::nextafter(1.0, 0.0)
    for (std::uint32_t k = 0; k < kUniforms; ++k) {
      double sum = static_cast<double>(words[2 * k]);
      sum += static_cast<double>(words[2 * k + 1]) * 4294967296.0;
      const double u = sum / 18446744073709551616.0;
      uniforms_[k] = u >= 1.0 ? kBelowOne : u;
    }
    next_ = 0;
  }
  Mt19937 rng_;
  double sigma_;
  double saved_ = 0.0;
  bool saved_available_ = false;
  std::uint32_t next_ = kUniforms;
  double uniforms_[kUniforms];
};

}  // namespace loopscan::sim
