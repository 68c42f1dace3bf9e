#include "loopscan/core/descriptors/m2dp.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "loopscan/core/descriptors/gray_mean.hpp"
#include "loopscan/core/descriptors/leading_singular.hpp"
#include "loopscan/core/descriptors/m2dp_bins.hpp"
#include "loopscan/core/descriptors/pca_align.hpp"
#include "loopscan/core/simd.hpp"

namespace loopscan {
namespace {

// Polar bin of a projected point; -1 if rejected. Default mode: sector by comparing against
// the boundary rays (no atan2), the +pi ray folded onto sector 0 instead of leaking.
struct PolarBinner {
  int sectors, rings;
  double sector_inv, ring_inv;
  bool reference;
  Eigen::VectorXd ray_cos, ray_sin;  // boundary rays inside one quadrant

  explicit PolarBinner(const M2dpConfig& c)
      : sectors(c.azimuth_bins),
        rings(c.radial_bins),
        sector_inv(c.azimuth_bins / (2.0 * M_PI)),
        ring_inv(c.radial_bins / c.max_radius_m),
        reference(c.mode == Mode::Reference) {
    const int per_quadrant = sectors % 4 == 0 ? sectors / 4 : 0;
    ray_cos.resize(std::max(per_quadrant - 1, 0));
    ray_sin.resize(ray_cos.size());
    for (Eigen::Index j = 0; j < ray_cos.size(); ++j) {
      const double a = (j + 1) * 2.0 * M_PI / sectors;
      ray_cos(j) = std::cos(a);
      ray_sin(j) = std::sin(a);
    }
  }

  int sector_of(double x, double y) const {
    if (reference || sectors % 4 != 0) {
      const int s = static_cast<int>(std::floor((std::atan2(y, x) + M_PI) * sector_inv));
      return reference ? s : s % sectors;
    }
    // atan2(y, x) + pi is the angle of (-x, -y) in [0, 2 pi): find its quadrant, rotate it
    // into the first one, count the boundary rays it has passed.
    const double X = -x, Y = -y;
    int quadrant;
    double u, v;
    if (X > 0 && Y >= 0) {
      quadrant = 0;
      u = X;
      v = Y;
    } else if (X <= 0 && Y > 0) {
      quadrant = 1;
      u = Y;
      v = -X;
    } else if (X < 0 && Y <= 0) {
      quadrant = 2;
      u = -X;
      v = -Y;
    } else {
      quadrant = 3;
      u = -Y;
      v = X;
    }
    int sub = 0;
    for (Eigen::Index j = 0; j < ray_cos.size(); ++j) sub += v * ray_cos(j) >= u * ray_sin(j);
    return quadrant * (sectors / 4) + sub;
  }

  int bin_of(double x, double y) const {
    const int ring = static_cast<int>(std::floor(std::sqrt(x * x + y * y) * ring_inv));
    if (!reference && ring >= rings) return -1;
    const int idx = ring * sectors + sector_of(x, y);
    return idx < rings * sectors ? idx : -1;
  }
};

// log1p of a count: counts are small integers, so a table of std::log1p (the same values),
// grown on demand up to 2^16 entries.
LOOPSCAN_INLINE double log1p_count(double c, std::vector<double>& table) {
  if (c >= 0 && c < static_cast<double>(table.size())) {
    const int k = static_cast<int>(c);  // the table holds at most 2^16 entries
    if (static_cast<double>(k) == c) return table[k];
  }
  constexpr double kMaxTable = 1 << 16;
  if (!(c >= 0 && c < kMaxTable) || c != std::floor(c)) return std::log1p(c);
  const auto k = static_cast<std::size_t>(c);
  while (table.size() <= k) table.push_back(std::log1p(static_cast<double>(table.size())));
  return table[k];
}

Eigen::RowVectorXd compressed(const Eigen::MatrixXd& m, Mode mode) {
  const SingularPair pair = leading_singular_pair(m, mode);
  Eigen::RowVectorXd out(pair.u.size() + pair.v.size());
  out << pair.u.transpose(), pair.v.transpose();
  return out;
}

}  // namespace

void m2dp_plane_axes(const M2dpConfig& c, Eigen::Matrix3Xd& x_axes, Eigen::Matrix3Xd& y_axes) {
  const int np = c.plane_azimuths, nq = c.plane_elevations;
  x_axes.resize(3, np * nq);
  y_axes.resize(3, np * nq);
  for (int p = 0; p < np; ++p) {
    for (int q = 0; q < nq; ++q) {
      Eigen::Vector3d n;
      if (c.mode == Mode::Reference) {
        const float azimuth = -M_PI / 2.0 + (M_PI / np) * p;
        const float elevation = (M_PI / 2.0 / nq) * q;
        n << std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
            std::sin(elevation);
      } else {
        const double azimuth = -M_PI / 2.0 + (M_PI / np) * p;
        const double elevation = (M_PI / 2.0 / nq) * q;
        n << std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
            std::sin(elevation);
      }
      // Projection of e_x on the plane, deliberately not re-normalised (as in the paper's code).
      const Eigen::Vector3d x_axis = Eigen::Vector3d::UnitX() - n.x() * n;
      x_axes.col(p * nq + q) = x_axis;
      y_axes.col(p * nq + q) = n.cross(x_axis);
    }
  }
}

namespace {

// Default mode's SoA of the aligned cloud flipped by (sx, sy, sx sy), padded to whole vectors
// (padding beyond the last ring). The flips are exact in float, so this is the SoA of the
// flipped cloud.
void fill_soa(const Cloud& aligned, float sx, float sy, PlanarCloud& soa) {
  const std::size_t padded = (aligned.size() + 15) / 16 * 16;
  soa.x.assign(padded, 1e30f);
  soa.y.assign(padded, 0.f);
  soa.z.assign(padded, 0.f);
  soa.gray.assign(padded, 0.f);
  for (std::size_t i = 0; i < aligned.size(); ++i) {
    soa.x[i] = sx * static_cast<float>(aligned[i].p(0));
    soa.y[i] = sy * static_cast<float>(aligned[i].p(1));
    soa.z[i] = (sx * sy) * static_cast<float>(aligned[i].p(2));
    soa.gray[i] = aligned[i].intensity;
  }
}

// Default mode's counts and gray sums (plane-major rows) of `soa`: one integer add a point when
// pack_gray succeeded (`packed`), else ordered double sums.
void bin_soa(const PlanarCloud& soa, bool packed, const M2dpBinner& binner,
             const Eigen::Matrix3Xd& x_axes, const Eigen::Matrix3Xd& y_axes, Eigen::Index bins,
             std::vector<double>& count, std::vector<double>& gray) {
  const Eigen::Index planes = x_axes.cols();
  count.assign(planes * bins, 0.0);
  gray.assign(planes * bins, 0.0);
  if (!packed) {
    for (Eigen::Index k = 0; k < planes; ++k) {
      binner.accumulate(soa, x_axes.col(k), y_axes.col(k), &count[k * bins], &gray[k * bins]);
    }
    return;
  }
  thread_local std::vector<long long> acc;
  acc.assign(planes * bins, 0);
  for (Eigen::Index k = 0; k < planes; ++k) {
    binner.accumulate_packed(soa, x_axes.col(k), y_axes.col(k), &acc[k * bins]);
  }
  const long long low_bits = (1LL << soa.count_shift) - 1;
  for (std::size_t i = 0; i < acc.size(); ++i) {
    count[i] = static_cast<double>(acc[i] >> soa.count_shift);
    gray[i] = static_cast<double>(acc[i] & low_bits) * soa.gray_unit;
  }
}

// The matrices (column-major) from plane-major counts and gray sums: the divisions in one
// contiguous loop (it vectorises), then both matrices written column by column.
M2dpMatrices finish(const std::vector<double>& count, const std::vector<double>& gray,
                    Eigen::Index planes, Eigen::Index bins, double mean, bool log_counts) {
  const std::size_t n = count.size();
  thread_local std::vector<double> above, table;
  above.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double c = count[i], q = gray[i] / c;  // empty bins: inf or NaN, masked
    above[i] = (c > 0) & (q > mean) ? 1.0 : 0.0;
  }
  M2dpMatrices m{Eigen::MatrixXd(planes, bins), Eigen::MatrixXd(planes, bins)};
  double* out_c = m.count.data();
  double* out_g = m.gray.data();
  for (Eigen::Index b = 0; b < bins; ++b) {
    for (Eigen::Index k = 0; k < planes; ++k) {
      const double c = count[k * bins + b];
      out_c[b * planes + k] = log_counts ? log1p_count(c, table) : c;
      out_g[b * planes + k] = above[k * bins + b];
    }
  }
  return m;
}

// log1p(k) for k = 0 .. n - 1 (std::log1p, the same values), n up to 2^16: a table kept per
// thread and grown on demand.
const std::vector<double>& log1p_table(std::size_t n) {
  thread_local std::vector<double> table;
  while (table.size() < n) table.push_back(std::log1p(static_cast<double>(table.size())));
  return table;
}

// One contiguous loop: the division (the costly part) vectorises, and no unpacked copies or
// transposition are made. The same operations as the unpacking in bin_soa() and finish().
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

// The default-mode matrices (planes x bins) from packed sums laid out like them (column-major:
// bin-major, acc[b * planes + k]), count = v >> shift, gray sum = (v & (2^shift - 1)) * unit:
// log1p(count) and (count > 0 && gray sum / count > mean), the values finish() makes from the
// unpacked counts and sums, in one contiguous pass. `max_count` bounds every count; below 2^16.
M2dpMatrices finish_packed(const std::vector<long long>& acc, int shift, double unit,
                           Eigen::Index planes, Eigen::Index bins, double mean,
                           std::size_t max_count) {
  const std::vector<double>& table = log1p_table(max_count + 1);
  M2dpMatrices m{Eigen::MatrixXd(planes, bins), Eigen::MatrixXd(planes, bins)};
  simd::widest(values_avx512, values_avx2, values_base)(
      acc.data(), acc.size(), shift, unit, mean, table.data(), m.count.data(), m.gray.data());
  return m;
}

}  // namespace

M2dpMatrices m2dp_matrices(const Cloud& aligned, const M2dpConfig& config) {
  Eigen::Matrix3Xd x_axes, y_axes;
  m2dp_plane_axes(config, x_axes, y_axes);
  const Eigen::Index planes = x_axes.cols(), bins = config.azimuth_bins * config.radial_bins;
  std::vector<double> count, gray;
  const M2dpBinner fast(config.azimuth_bins, config.radial_bins, config.max_radius_m);
  if (config.mode == Mode::Default && fast.usable()) {
    thread_local PlanarCloud soa;
    fill_soa(aligned, 1.f, 1.f, soa);
    const bool packed = pack_gray(soa, soa.x.size());
    bin_soa(soa, packed, fast, x_axes, y_axes, bins, count, gray);
  } else {
    count.assign(planes * bins, 0.0);
    gray.assign(planes * bins, 0.0);
    const PolarBinner binner(config);
    for (Eigen::Index k = 0; k < planes; ++k) {
      const Eigen::Vector3d xa = x_axes.col(k), ya = y_axes.col(k);
      for (const PointI& q : aligned) {
        const int i = binner.bin_of(xa.dot(q.p), ya.dot(q.p));
        if (i < 0) continue;
        count[k * bins + i] += 1;
        gray[k * bins + i] += q.intensity;
      }
    }
  }
  // Default mode compresses log(1 + count): with raw counts the singular vectors follow the
  // densest bins, whose density is what two VO runs share least.
  return finish(count, gray, planes, bins, cloud_gray_mean(aligned, config.mode),
                config.mode == Mode::Default);
}

Signature m2dp_signature(const Cloud& scan, const M2dpConfig& config) {
  validate(config);
  const int planes = config.plane_azimuths * config.plane_elevations;
  const int half = planes + config.azimuth_bins * config.radial_bins;
  Signature sig = Signature::Zero(4, 2 * half);
  thread_local Cloud aligned;
  align_scan(scan, config.frame, config.mode, aligned);
  const M2dpBinner fast(config.azimuth_bins, config.radial_bins, config.max_radius_m);
  if (config.mode == Mode::Default && fast.usable()) {
    // m2dp_matrices of each flipped cloud, with what the flips leave unchanged done once: the
    // planes, the gray mean and the packed gray values (the same for every flip).
    Eigen::Matrix3Xd x_axes, y_axes;
    m2dp_plane_axes(config, x_axes, y_axes);
    const Eigen::Index bins = config.azimuth_bins * config.radial_bins;
    const double mean = cloud_gray_mean(aligned, config.mode);
    thread_local PlanarCloud soa;
    thread_local std::vector<double> count, gray;
    thread_local std::vector<long long> acc;
    fill_soa(aligned, 1.f, 1.f, soa);
    // Packed sums straight into the matrices' layout (bin-major) and finished in one pass.
    const bool packed = pack_gray(soa, soa.x.size()), direct = packed && soa.x.size() < 65535;
    int row = 0;
    for (int sx = -1; sx <= 1; sx += 2) {
      for (int sy = -1; sy <= 1; sy += 2) {
        for (std::size_t i = 0; i < aligned.size(); ++i) {
          soa.x[i] = sx * static_cast<float>(aligned[i].p(0));
          soa.y[i] = sy * static_cast<float>(aligned[i].p(1));
          soa.z[i] = (sx * sy) * static_cast<float>(aligned[i].p(2));
        }
        M2dpMatrices m;
        if (direct) {
          acc.assign(planes * bins, 0);
          for (int k = 0; k < planes; ++k) {
            fast.accumulate_packed(soa, x_axes.col(k), y_axes.col(k), &acc[k], planes);
          }
          m = finish_packed(acc, soa.count_shift, soa.gray_unit, planes, bins, mean, soa.x.size());
        } else {
          bin_soa(soa, packed, fast, x_axes, y_axes, bins, count, gray);
          m = finish(count, gray, planes, bins, mean, true);
        }
        sig.row(row).head(half) = compressed(m.count, config.mode);
        sig.row(row).tail(half) = compressed(m.gray, config.mode);
        ++row;
      }
    }
    return sig;
  }
  Cloud flipped(aligned.size());
  int row = 0;
  for (int sx = -1; sx <= 1; sx += 2) {
    for (int sy = -1; sy <= 1; sy += 2) {
      for (std::size_t i = 0; i < aligned.size(); ++i) {
        const Eigen::Vector3d& a = aligned[i].p;
        flipped[i] = {{sx * a(0), sy * a(1), (sx * sy) * a(2)}, aligned[i].intensity};
      }
      const M2dpMatrices m = m2dp_matrices(flipped, config);
      sig.row(row).head(half) = compressed(m.count, config.mode);
      sig.row(row).tail(half) = compressed(m.gray, config.mode);
      ++row;
    }
  }
  return sig;
}

}  // namespace loopscan
