#pragma once
// Default-mode M2DP binning, vectorised: projects points on one plane, finds each point's polar
// bin (ring * sectors + sector; none beyond the last ring) in single precision, several points
// per instruction, and adds it to the plane's count and gray-sum rows. The sector comes from
// comparisons against the boundary rays instead of atan2; ties at exact boundaries may fall on
// either side, as any rounding could.
#include <vector>

#include <Eigen/Core>

namespace loopscan {

struct PlanarCloud {  // structure of arrays, padded to whole SIMD vectors
  std::vector<float> x, y, z, gray;
  std::size_t size = 0;
  // pack_gray: per point (1 << count_shift) + gray / gray_unit, an exact integer.
  std::vector<long long> packed;
  double gray_unit = 1.0;
  int count_shift = 0;
};

// When every gray sum of the cloud's first n points is exact in double whatever the order (all
// values multiples of one power of two, sums far below 2^53 of it), fills `packed` and returns
// true: one integer add a point then counts and sums it, and the sums equal the ordered double
// sums bit for bit. False (negative, huge or subnormal values): use accumulate().
bool pack_gray(PlanarCloud& cloud, std::size_t n);

class M2dpBinner {
 public:
  M2dpBinner(int sectors, int rings, double max_radius_m);
  // Sectors: a power of two, 4 to 32 (16 in the paper).
  bool usable() const { return sectors_ == (1 << shift_) && sectors_ >= 4 && sectors_ <= 32; }
  // count_row[bin] += 1 and gray_row[bin] += gray for every point projected on the plane.
  void accumulate(const PlanarCloud& cloud, const Eigen::Vector3d& x_axis,
                  const Eigen::Vector3d& y_axis, double* count_row, double* gray_row) const;
  // packed_row[bin * stride] += cloud.packed[i] (pack_gray) for every point: count and gray
  // sum at once.
  void accumulate_packed(const PlanarCloud& cloud, const Eigen::Vector3d& x_axis,
                         const Eigen::Vector3d& y_axis, long long* packed_row,
                         std::size_t stride = 1) const;

 private:
  int sectors_, rings_;
  double max_radius_;
  int shift_ = 0;                         // log2(sectors)
  std::vector<float> ray_cos_, ray_sin_;  // boundary rays inside a quadrant
};

}  // namespace loopscan
