#include "loopscan/core/descriptors/m2dp_finish.hpp"

#include <cmath>

#include "loopscan/core/simd.hpp"

namespace loopscan {

const std::vector<double>& log1p_table(std::size_t n) {
  thread_local std::vector<double> table;
  while (table.size() < n) table.push_back(std::log1p(static_cast<double>(table.size())));
  return table;
}

namespace {

// One contiguous loop: the division (the costly part) vectorises, and no unpacked copies or
// transposition are made. The same operations as the unpacking in m2dp.cpp and finish().
LOOPSCAN_INLINE void values(const long long* acc, std::size_t n, int shift, double unit,
                            double mean, const double* table, double* out_c, double* out_g) {
  const long long low_bits = (1LL << shift) - 1;
  for (std::size_t i = 0; i < n; ++i) {
    const long long k = acc[i] >> shift;
    const double c = static_cast<double>(k);
    const double q = static_cast<double>(acc[i] & low_bits) * unit / c;  // empty: NaN, masked
    out_g[i] = (c > 0) & (q > mean) ? 1.0 : 0.0;
    out_c[i] = table[k];
  }
}

void values_base(const long long* acc, std::size_t n, int shift, double unit, double mean,
                 const double* table, double* out_c, double* out_g) {
  values(acc, n, shift, unit, mean, table, out_c, out_g);
}
LOOPSCAN_AVX2 void values_avx2(const long long* acc, std::size_t n, int shift, double unit,
                               double mean, const double* table, double* out_c, double* out_g) {
  values(acc, n, shift, unit, mean, table, out_c, out_g);
}
LOOPSCAN_AVX512 void values_avx512(const long long* acc, std::size_t n, int shift, double unit,
                                   double mean, const double* table, double* out_c, double* out_g) {
  values(acc, n, shift, unit, mean, table, out_c, out_g);
}

}  // namespace

M2dpMatrices finish_packed(const std::vector<long long>& acc, int shift, double unit,
                           Eigen::Index planes, Eigen::Index bins, double mean,
                           std::size_t max_count) {
  const std::vector<double>& table = log1p_table(max_count + 1);
  M2dpMatrices m{Eigen::MatrixXd(planes, bins), Eigen::MatrixXd(planes, bins)};
  simd::widest(values_avx512, values_avx2, values_base)(
      acc.data(), acc.size(), shift, unit, mean, table.data(), m.count.data(), m.gray.data());
  return m;
}

}  // namespace loopscan
