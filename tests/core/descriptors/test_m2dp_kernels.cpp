// M2DP's linear-algebra kernels (power_step.hpp, leading_singular.hpp) against Eigen and
// against each other, bit for bit: the signatures were made with these bits.
#include <gtest/gtest.h>

#include <Eigen/Core>

#include <cmath>
#include <cstring>
#include <random>
#include <utility>

#include "loopscan/core/descriptors/leading_singular.hpp"
#include "loopscan/core/descriptors/power_step.hpp"

namespace loopscan {
namespace {

// The power iteration's product against Eigen's (the bits the signatures were made with): every
// block and tail size, signed zeros, cancellations.
TEST(M2dpOracle, PowerStepEqualsEigensProductBitForBit) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int n : {1, 2, 3, 7, 8, 9, 16, 63, 64, 65, 100, 130}) {
    Eigen::MatrixXd g(n, n);
    Eigen::VectorXd v(n), got(n);
    for (int trial = 0; trial < 4; ++trial) {
      for (Eigen::Index i = 0; i < g.size(); ++i) {
        const double x = u(rng);
        g.data()[i] = trial == 1 && x < -0.5 ? -0.0 : trial == 2 ? std::ldexp(x, -40 * (i % 3)) : x;
      }
      for (int j = 0; j < n; ++j) v(j) = trial == 3 ? (j % 2 ? -0.0 : 0.0) : u(rng) * 1e3;
      const Eigen::VectorXd want = g * v;
      gram_times(g.data(), n, v.data(), got.data());
      EXPECT_EQ(std::memcmp(got.data(), want.data(), sizeof(double) * n), 0) << n << " " << trial;
    }
  }
}

// The AVX-512 Gram kernel against the AVX2 one: the same bits (every row tail; lengths of
// whole 4-lane chunks, as M2DP's, the others keeping the AVX2 kernel).
TEST(M2dpOracle, GramKernelsAgreeBitForBit) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const auto& [rows, cols] :
       {std::pair{64, 128}, {13, 36}, {8, 4}, {1, 8}, {70, 132}, {9, 37}}) {
    Eigen::MatrixXd a(rows, cols);
    for (Eigen::Index i = 0; i < a.size(); ++i) {
      const double x = u(rng);
      a.data()[i] = x < -0.7 ? -0.0 : x < -0.4 ? 0.0 : std::log1p(std::ldexp(x + 1, i % 40));
    }
    const Eigen::MatrixXd wide = gram_matrix_for_width(a, 64), avx2 = gram_matrix_for_width(a, 32);
    EXPECT_EQ(std::memcmp(wide.data(), avx2.data(), sizeof(double) * wide.size()), 0) << rows;
  }
}

}  // namespace
}  // namespace loopscan
