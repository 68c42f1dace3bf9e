// Fast descriptor paths against straightforward re-implementations (std::atan2, std::sqrt,
// one centre at a time), bit for bit, on random clouds and on points placed on bin boundaries;
// M2DP's linear-algebra kernels against Eigen and against each other, bit for bit: the
// signatures were made with these bits.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <cstring>
#include <random>
#include <utility>

#include "loopscan/core/descriptors/describe.hpp"
#include "loopscan/core/descriptors/leading_singular.hpp"
#include "loopscan/core/descriptors/m2dp.hpp"
#include "loopscan/core/descriptors/m2dp_bins.hpp"
#include "loopscan/core/descriptors/pca_align.hpp"
#include "loopscan/core/descriptors/scan_context.hpp"
#include "loopscan/core/simd.hpp"
#include "support/test_support.hpp"

namespace loopscan {
namespace {

// Default-mode Scan Context of one centre, written from the definition.
Eigen::RowVectorXd scan_context_oracle(const Cloud& aligned, const ScanContextConfig& c, double cx,
                                       double cy) {
  const int R = c.rings, S = c.sectors, B = R * S;
  double mean = 0;
  for (const PointI& q : aligned) mean += q.intensity;
  if (!aligned.empty()) mean /= static_cast<double>(aligned.size());
  std::vector<double> low(B), high(B), gray(B), count(B);
  for (const PointI& q : aligned) {
    const double a1 = q.p(1) - cx, a2 = q.p(2) - cy;
    const int ring =
        static_cast<int>(std::floor(std::sqrt(a1 * a1 + a2 * a2) * (R / c.max_radius_m)));
    if (ring >= R) continue;
    const int sector =
        static_cast<int>(std::floor((std::atan2(a2, a1) + M_PI) * (S / (2.0 * M_PI)))) % S;
    const int b = sector * R + ring;
    const double h = q.p(0);
    low[b] = count[b] == 0 ? h : std::min(low[b], h);
    high[b] = count[b] == 0 ? h : std::max(high[b], h);
    gray[b] += q.intensity;
    count[b] += 1;
  }
  Eigen::RowVectorXd row(2 * B);
  for (int b = 0; b < B; ++b) {
    const bool any = count[b] > 0;
    row(b) =
        c.max_height ? (any ? std::max(0.0, high[b] + c.sensor_height_m) : 0.0) : high[b] - low[b];
    row(B + b) = any && gray[b] / count[b] > mean ? 1.0 : 0.0;
  }
  return row;
}

// Random points plus points on sector rays, ring circles, the axes and the centres themselves.
Cloud boundary_cloud(unsigned seed, const ScanContextConfig& c) {
  Cloud cloud = test::street_cloud(seed, 1500);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-50.0, 50.0);
  auto add = [&](double x, double z) {  // camera frame: x right, y down, z forward
    cloud.push_back({{x, u(rng) / 10, z}, static_cast<float>(rng() % 256)});
  };
  for (int i = 0; i < 300; ++i) add(u(rng), u(rng));
  for (double tiny : {1e-42, 3e-39, 1e-300, 1e-20}) {  // next to the place's centre
    add(tiny, tiny * 0.3);
    add(-tiny * 0.2, tiny);
    add(-tiny, -tiny * 0.9);
  }
  for (double off : {0.0, -3.5, -1.75, 1.75, 3.5}) {
    add(off, 0.0);  // a version's centre
    for (int s = 0; s < 2 * c.sectors; ++s) {
      const double a = s * M_PI / c.sectors, r = std::abs(u(rng)) * 0.9;
      add(off + r * std::cos(a), r * std::sin(a));  // on (or halfway between) sector rays
    }
    for (int k = 0; k <= c.rings; ++k) {
      const double r = k * c.max_radius_m / c.rings;
      add(off + r, 0.0);
      add(off, -r);
      add(off - r * std::sqrt(0.5), r * std::sqrt(0.5));
    }
  }
  return cloud;
}

TEST(ScanContextOracle, OnePassVersionsEqualTheDefinition) {
  std::vector<ScanContextConfig> configs;
  for (int sectors : {60, 40, 120}) {
    for (int rings : {20, 7}) {
      ScanContextConfig c = DescriptorConfig::for_mode(Mode::Default).scan_context;
      c.sectors = sectors;
      c.rings = rings;
      configs.push_back(c);
    }
  }
  configs.push_back(configs.front());
  configs.back().max_height = true;
  configs.push_back(configs.front());
  configs.back().frame = DescriptorFrame::Centroid;
  int compared = 0;
  for (const ScanContextConfig& c : configs) {
    for (unsigned seed : {1u, 2u, 3u}) {
      const Cloud scan = boundary_cloud(seed, c);
      Eigen::Matrix3d axes;
      const Cloud aligned = align_scan(scan, c.frame, c.mode, &axes, c.lateral_offset_m);
      const Signature fast = scan_context_signature(scan, c);
      ASSERT_EQ(fast.rows(), 1 + static_cast<Eigen::Index>(c.lateral_versions_m.size()));
      for (Eigen::Index v = 0; v < fast.rows(); ++v) {
        const double off = v > 0 ? c.lateral_versions_m[v - 1] : 0.0;
        const Eigen::Vector3d side = axes * Eigen::Vector3d(off, 0, 0);
        const Eigen::RowVectorXd want = scan_context_oracle(aligned, c, side(1), side(2));
        ASSERT_EQ(fast.row(v), want)
            << c.sectors << " x " << c.rings << " seed " << seed << " version " << v;
        ++compared;
      }
    }
  }
  EXPECT_EQ(compared, 8 * 3 * 5);
}

TEST(ScanContextOracle, EmptyAndSinglePointScans) {
  const ScanContextConfig c = DescriptorConfig::for_mode(Mode::Default).scan_context;
  EXPECT_EQ(scan_context_signature({}, c).sum(), 0.0);
  const Cloud one{{{0.0, 0.0, 0.0}, 7.f}};  // at the place's own centre: ring 0
  const Signature s = scan_context_signature(one, c);
  EXPECT_EQ(s.row(0), scan_context_oracle(align_scan(one, c.frame, c.mode), c, 0.0, 0.0));
  for (int n = 1; n <= 19; ++n) {  // every tail length of the 2-, 4- and 8-lane kernels
    const Cloud small = test::street_cloud(n, n);
    const Cloud aligned = align_scan(small, c.frame, c.mode);
    EXPECT_EQ(scan_context_signature(small, c).row(0), scan_context_oracle(aligned, c, 0.0, 0.0))
        << n;
  }
}

PlanarCloud planar(const Cloud& aligned) {
  PlanarCloud soa;
  const std::size_t padded = (aligned.size() + 15) / 16 * 16;
  soa.x.assign(padded, 1e30f);
  soa.y.assign(padded, 0.f);
  soa.z.assign(padded, 0.f);
  soa.gray.assign(padded, 0.f);
  for (std::size_t i = 0; i < aligned.size(); ++i) {
    soa.x[i] = static_cast<float>(aligned[i].p(0));
    soa.y[i] = static_cast<float>(aligned[i].p(1));
    soa.z[i] = static_cast<float>(aligned[i].p(2));
    soa.gray[i] = aligned[i].intensity;
  }
  return soa;
}

// Points whose projections on the planes land on ring circles and sector rays (to within the
// rounding of the floats), where kernels that round differently disagree.
void add_boundary_points(const M2dpConfig& cfg, const Eigen::Matrix3Xd& xa,
                         const Eigen::Matrix3Xd& ya, std::mt19937& rng, Cloud& cloud) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (Eigen::Index k = 0; k < xa.cols(); ++k) {
    const Eigen::Vector3d x = xa.col(k), y = ya.col(k);
    if (x.squaredNorm() == 0 || y.squaredNorm() == 0) continue;
    const Eigen::Vector3d n = x.cross(y).normalized();
    for (int i = 0; i < 24; ++i) {
      double r, a;
      if (i % 2 == 0) {  // on a ring circle
        r = (1 + static_cast<int>(u(rng) * cfg.radial_bins)) * cfg.max_radius_m / cfg.radial_bins;
        a = 2 * M_PI * u(rng);
      } else {  // on a sector ray
        r = cfg.max_radius_m * u(rng);
        a = static_cast<int>(u(rng) * cfg.azimuth_bins) * 2 * M_PI / cfg.azimuth_bins;
      }
      const Eigen::Vector3d p = r * std::cos(a) * x / x.squaredNorm() +
                                r * std::sin(a) * y / y.squaredNorm() + 10 * (u(rng) - 0.5) * n;
      cloud.push_back({p, static_cast<float>(std::floor(255 * u(rng)))});
    }
  }
}

// The packed integer accumulation (count and gray sum in one add) against the ordered double
// sums, bit for bit, for gray values of every kind; and m2dp_matrices against the double path.
TEST(M2dpOracle, PackedSumsEqualOrderedDoubleSums) {
  const M2dpConfig cfg;
  Eigen::Matrix3Xd xa, ya;
  m2dp_plane_axes(cfg, xa, ya);
  const M2dpBinner binner(cfg.azimuth_bins, cfg.radial_bins, cfg.max_radius_m);
  const int bins = cfg.azimuth_bins * cfg.radial_bins;
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> u(0.f, 255.f);
  int packed_runs = 0, plain_runs = 0;
  for (int kind = 0; kind < 5; ++kind) {
    for (int n : {2000, 2001, 6343}) {
      Cloud aligned = pca_align(test::street_cloud(kind + 1, n), Mode::Default);
      add_boundary_points(cfg, xa, ya, rng, aligned);
      for (std::size_t i = 0; i < aligned.size(); ++i) {
        float& g = aligned[i].intensity;
        if (kind == 0) g = std::floor(u(rng));                    // gray levels
        if (kind == 1) g = u(rng);                                // any float in 0..255
        if (kind == 2) g = i % 3 == 0 ? u(rng) * 1e-4f : u(rng);  // too fine to pack
        if (kind == 3) g = i % 7 == 0 ? 0.f : 1.f / (1 + i % 13);
        if (kind == 4) g = u(rng) - 10.f;  // negative: the double path
      }
      PlanarCloud soa = planar(aligned);
      const bool packed = pack_gray(soa, soa.gray.size());
      EXPECT_EQ(packed, kind != 2 && kind != 4) << kind;
      (packed ? packed_runs : plain_runs)++;
      std::vector<double> count(xa.cols() * bins, 0.0), gray(count.size(), 0.0);
      for (Eigen::Index k = 0; k < xa.cols(); ++k) {
        binner.accumulate(soa, xa.col(k), ya.col(k), &count[k * bins], &gray[k * bins]);
      }
      if (packed) {
        std::vector<long long> acc(count.size(), 0);
        for (Eigen::Index k = 0; k < xa.cols(); ++k) {
          binner.accumulate_packed(soa, xa.col(k), ya.col(k), &acc[k * bins]);
        }
        for (std::size_t i = 0; i < acc.size(); ++i) {
          ASSERT_EQ(static_cast<double>(acc[i] >> soa.count_shift), count[i]) << kind << " " << i;
          const long long low = acc[i] & ((1LL << soa.count_shift) - 1);
          ASSERT_EQ(static_cast<double>(low) * soa.gray_unit, gray[i]) << kind << " " << i;
        }
      }
      // m2dp_matrices (whichever path it takes) against the ordered sums.
      const M2dpMatrices m = m2dp_matrices(aligned, cfg);
      double mean = 0;
      for (const PointI& q : aligned) mean += q.intensity;
      mean /= static_cast<double>(aligned.size());
      for (Eigen::Index k = 0; k < xa.cols(); ++k) {
        for (int b = 0; b < bins; ++b) {
          const double c = count[k * bins + b], g = gray[k * bins + b];
          ASSERT_EQ(m.count(k, b), std::log1p(c));
          ASSERT_EQ(m.gray(k, b), c > 0 && g / c > mean ? 1.0 : 0.0);
        }
      }
    }
  }
  EXPECT_EQ(packed_runs, 9);
  EXPECT_EQ(plain_runs, 6);
}

// m2dp_signature (one SoA and one packing for the four flips) against its definition: each
// flipped cloud through m2dp_matrices, both matrices compressed, bit for bit.
TEST(M2dpOracle, SignatureEqualsFlippedMatricesCompressed) {
  const M2dpConfig cfg;
  for (int n : {1, 17, 2001, 6343}) {
    Cloud scan = test::street_cloud(n, n);
    if (n == 17) {
      for (PointI& q : scan) q.intensity -= 100.f;  // negative: the double path
    }
    const Signature sig = m2dp_signature(scan, cfg);
    const Cloud aligned = align_scan(scan, cfg.frame, cfg.mode);
    int row = 0;
    for (int sx = -1; sx <= 1; sx += 2) {
      for (int sy = -1; sy <= 1; sy += 2) {
        Cloud flipped = aligned;
        for (PointI& q : flipped) q.p = Eigen::Vector3d(sx * q.p(0), sy * q.p(1), sx * sy * q.p(2));
        const M2dpMatrices m = m2dp_matrices(flipped, cfg);
        Eigen::RowVectorXd expected(sig.cols());
        const SingularPair c = leading_singular_pair(m.count, cfg.mode);
        const SingularPair g = leading_singular_pair(m.gray, cfg.mode);
        expected << c.u.transpose(), c.v.transpose(), g.u.transpose(), g.v.transpose();
        EXPECT_EQ(sig.row(row), expected) << n << " flip " << row;
        ++row;
      }
    }
  }
}

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
  if (!simd::has_avx512()) {
    GTEST_SKIP() << "the AVX-512 kernel does not run here (no AVX-512, or LOOPSCAN_NO_AVX512 / "
                    "LOOPSCAN_NO_AVX2 set): both widths would run the same kernel";
  }
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
