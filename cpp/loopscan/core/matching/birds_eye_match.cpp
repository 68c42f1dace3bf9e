#include "loopscan/core/matching/birds_eye_match.hpp"

#include "loopscan/core/peak_vertex.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace loopscan {
namespace {

double squared_norm(const std::vector<std::int8_t>& v) {
  double s = 0;
  for (std::int8_t x : v) s += double(x) * double(x);
  return s;
}

void check_images(const BirdsEyePlace& query, const BirdsEyePlace& place,
                  const BirdsEyePlaceConfig& config) {
  const int side = image_side(config);
  const std::size_t cells = std::size_t(side) * std::size_t(side);
  if (query.side != side || place.side != side || query.image.size() != cells ||
      place.image.size() != cells) {
    throw std::invalid_argument("birds_eye: images of " + std::to_string(side) + " x " +
                                std::to_string(side) + " cells expected");
  }
}

// The place image turned by yaw into the query's orientation: cell p of the result samples the
// place at R(yaw)^T p (bilinear; zero outside).
std::vector<float> turned_image(const BirdsEyePlace& place, double yaw, double cell_m,
                                double range_m) {
  const int n = place.side;
  std::vector<float> out(std::size_t(n) * std::size_t(n), 0.f);
  const double c = std::cos(yaw), s = std::sin(yaw);
  auto at = [&](int r, int col) -> double {
    if (r < 0 || r >= n || col < 0 || col >= n) return 0.0;
    return place.image[std::size_t(r) * n + col];
  };
  for (int r = 0; r < n; ++r) {
    const double z = (r + 0.5) * cell_m - range_m;
    for (int col = 0; col < n; ++col) {
      const double x = (col + 0.5) * cell_m - range_m;
      // R^T (x, z): R turns x towards z by yaw.
      const double px = c * x + s * z, pz = -s * x + c * z;
      const double fc = (px + range_m) / cell_m - 0.5, fr = (pz + range_m) / cell_m - 0.5;
      const double c0 = std::floor(fc), r0 = std::floor(fr);
      const double wc = fc - c0, wr = fr - r0;
      const int ci = int(c0), ri = int(r0);
      out[std::size_t(r) * n + col] =
          float((1 - wr) * ((1 - wc) * at(ri, ci) + wc * at(ri, ci + 1)) +
                wr * ((1 - wc) * at(ri + 1, ci) + wc * at(ri + 1, ci + 1)));
    }
  }
  return out;
}

double wrap_angle(double a) {
  a = std::remainder(a, 2 * M_PI);
  return a <= -M_PI ? a + 2 * M_PI : a;
}

// cos and sin of 2 pi i / A, and per shift s the terms' cos and sin of 2 pi k s / A.
struct UnitCircle {
  int angles = 0;
  std::vector<double> cos, sin;
  std::vector<float> shift_cos, shift_sin;  // angles x (angles / 2 + 1)
};

const UnitCircle& unit_circle(int angles) {
  thread_local UnitCircle circle;
  if (circle.angles == angles) return circle;
  const int terms = angles / 2 + 1;
  circle.angles = angles;
  circle.cos.resize(angles);
  circle.sin.resize(angles);
  for (int i = 0; i < angles; ++i) {
    circle.cos[i] = std::cos(2 * M_PI * i / angles);
    circle.sin[i] = std::sin(2 * M_PI * i / angles);
  }
  circle.shift_cos.resize(std::size_t(angles) * terms);
  circle.shift_sin.resize(std::size_t(angles) * terms);
  for (int s = 0; s < angles; ++s) {
    for (int k = 0; k < terms; ++k) {
      const int i = (k * s) % angles;
      circle.shift_cos[std::size_t(s) * terms + k] = float(circle.cos[i]);
      circle.shift_sin[std::size_t(s) * terms + k] = float(circle.sin[i]);
    }
  }
  return circle;
}

// The query image zero-padded by max_cells on every side, and its norm: what every turned
// place is correlated with, built once per query and place.
struct PaddedQuery {
  PaddedQuery(const BirdsEyePlace& query, int max_cells)
      : n(query.side), m(max_cells), side(query.side + 2 * max_cells),
        cells(std::size_t(side) * std::size_t(side), 0.f) {
    double sq = 0;
    for (int r = 0; r < n; ++r) {
      for (int c = 0; c < n; ++c) {
        const float v = query.image[std::size_t(r) * n + c];
        cells[std::size_t(r + m) * side + c + m] = v;
        sq += double(v) * v;
      }
    }
    norm = std::sqrt(sq);
  }
  int n, m, side;
  std::vector<float> cells;
  double norm = 0;
};

// birds_eye_correlation on a padded query: sparse over the turned place (most cells hold no
// structure), each place cell adding a contiguous run of the padded query.
std::vector<double> correlate(const PaddedQuery& query, const BirdsEyePlace& place,
                              double yaw_rad, const BirdsEyePlaceConfig& config) {
  const int n = query.n, w = 2 * query.m + 1;
  std::vector<double> out(std::size_t(w) * std::size_t(w), 0.0);
  const std::vector<float> turned = turned_image(place, yaw_rad, config.cell_m, config.range_m);
  double turned_sq = 0;
  for (float v : turned) turned_sq += double(v) * v;
  const double norms = std::sqrt(turned_sq) * query.norm;
  if (!(norms > 0)) return out;
  std::vector<float> sums(out.size(), 0.f);
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) {
      const float v = turned[std::size_t(r) * n + c];
      if (v == 0.f) continue;
      for (int dz = 0; dz < w; ++dz) {  // query row r + dz - m, columns c - m .. c + m
        const float* row = query.cells.data() + std::size_t(r + dz) * query.side + c;
        float* o = sums.data() + std::size_t(dz) * w;
        for (int dx = 0; dx < w; ++dx) o[dx] += v * row[dx];
      }
    }
  }
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = sums[i] / norms;
  return out;
}

}  // namespace

BirdsEyeKeyMatch match_keys(const BirdsEyePlace& query, const BirdsEyePlace& place, int angles) {
  if (angles < 1 || query.key.size() != place.key.size() || query.key.size() % angles != 0) {
    throw std::invalid_argument("birds_eye: keys of equal size, whole rings of " +
                                std::to_string(angles) + " angles expected");
  }
  BirdsEyeKeyMatch best;
  const double norms = std::sqrt(squared_norm(query.key) * squared_norm(place.key));
  if (!(norms > 0)) return best;
  const int rings = int(query.key.size()) / angles;
  const std::int8_t* q = query.key.data();
  const std::int8_t* d = place.key.data();
  double top = -1e300;
  int top_shift = 0;
  for (int shift = 0; shift < angles; ++shift) {  // q[a] against d[a - shift]
    long long sum = 0;
    for (int r = 0; r < rings; ++r) {
      const std::int8_t* qr = q + std::size_t(r) * angles;
      const std::int8_t* dr = d + std::size_t(r) * angles;
      for (int a = 0; a < shift; ++a) sum += int(qr[a]) * int(dr[a - shift + angles]);
      for (int a = shift; a < angles; ++a) sum += int(qr[a]) * int(dr[a - shift]);
    }
    if (double(sum) > top) {
      top = double(sum);
      top_shift = shift;
    }
  }
  best.distance = 1.0 - top / norms;
  best.yaw_rad = top_shift * M_PI / angles;
  return best;
}

BirdsEyeKeySpectrum key_spectrum(const BirdsEyePlace& place, int angles) {
  if (angles < 2 || place.key.size() % std::size_t(angles) != 0) {
    throw std::invalid_argument("birds_eye: a key of whole rings of " + std::to_string(angles) +
                                " angles expected");
  }
  BirdsEyeKeySpectrum s;
  s.rings = int(place.key.size()) / angles;
  s.angles = angles;
  const int terms = angles / 2 + 1;
  s.re.assign(std::size_t(s.rings) * terms, 0.f);
  s.im.assign(std::size_t(s.rings) * terms, 0.f);
  s.norm = std::sqrt(squared_norm(place.key));
  const UnitCircle& circle = unit_circle(angles);
  for (int r = 0; r < s.rings; ++r) {
    const std::int8_t* v = place.key.data() + std::size_t(r) * angles;
    for (int k = 0; k < terms; ++k) {
      double re = 0, im = 0;
      for (int a = 0; a < angles; ++a) {
        const int i = int((std::int64_t(k) * a) % angles);  // e^{-2 pi i k a / A}
        re += v[a] * circle.cos[i];
        im -= v[a] * circle.sin[i];
      }
      s.re[std::size_t(r) * terms + k] = float(re);
      s.im[std::size_t(r) * terms + k] = float(im);
    }
  }
  return s;
}

BirdsEyeKeyMatch match_key_spectra(const BirdsEyeKeySpectrumView& query,
                                   const BirdsEyeKeySpectrumView& place) {
  if (query.rings != place.rings || query.angles != place.angles || query.angles < 2) {
    throw std::invalid_argument("birds_eye: key spectra of the same rings and angles expected");
  }
  BirdsEyeKeyMatch best;
  const double norms = query.norm * place.norm;
  if (!(norms > 0)) return best;
  const int A = query.angles, terms = A / 2 + 1;
  // X_k = sum over rings of Q_k conj(D_k): the cross spectrum of the two keys.
  thread_local std::vector<float> xr, xi;
  xr.assign(terms, 0.f);
  xi.assign(terms, 0.f);
  for (int r = 0; r < query.rings; ++r) {
    const float* qr = query.re + std::size_t(r) * terms;
    const float* qi = query.im + std::size_t(r) * terms;
    const float* dr = place.re + std::size_t(r) * terms;
    const float* di = place.im + std::size_t(r) * terms;
    for (int k = 0; k < terms; ++k) {
      xr[k] += qr[k] * dr[k] + qi[k] * di[k];
      xi[k] += qi[k] * dr[k] - qr[k] * di[k];
    }
  }
  // corr(s) = (1/A) sum_k X_k e^{2 pi i k s / A}, the conjugate-symmetric half counted twice.
  const UnitCircle& circle = unit_circle(A);
  for (int k = 1; k < terms; ++k) {
    const float w = (2 * k == A) ? 1.f : 2.f;
    xr[k] *= w;
    xi[k] *= w;
  }
  double top = -1e300;
  int top_shift = 0;
  for (int s = 0; s < A; ++s) {
    const float* c = circle.shift_cos.data() + std::size_t(s) * terms;
    const float* sn = circle.shift_sin.data() + std::size_t(s) * terms;
    float sum = 0.f;
    for (int k = 0; k < terms; ++k) sum += xr[k] * c[k] - xi[k] * sn[k];
    if (sum > top) {
      top = sum;
      top_shift = s;
    }
  }
  best.distance = 1.0 - top / (A * norms);
  best.yaw_rad = top_shift * M_PI / A;
  return best;
}

std::vector<double> birds_eye_correlation(const BirdsEyePlace& query, const BirdsEyePlace& place,
                                          double yaw_rad, const BirdsEyePlaceConfig& config,
                                          int max_cells) {
  check_images(query, place, config);
  return correlate(PaddedQuery(query, max_cells), place, yaw_rad, config);
}

BirdsEyePose birds_eye_pose(const BirdsEyePlace& query, const BirdsEyePlace& place,
                            double key_yaw_rad, const BirdsEyePlaceConfig& config,
                            const BirdsEyeSearchConfig& search) {
  check_images(query, place, config);
  if (!(search.max_shift_m >= 0) || search.yaw_steps < 0) {
    throw std::invalid_argument("birds_eye: max_shift_m >= 0 and yaw_steps >= 0 expected");
  }
  const int m = int(std::floor(search.max_shift_m / config.cell_m)), w = 2 * m + 1;
  const double step = M_PI / config.angles;
  const PaddedQuery padded(query, m);
  BirdsEyePose best;
  best.score = -1;
  for (double base : {key_yaw_rad, key_yaw_rad + M_PI}) {
    for (int k = -search.yaw_steps; k <= search.yaw_steps; ++k) {
      const double yaw = wrap_angle(base + k * step);
      const std::vector<double> corr = correlate(padded, place, yaw, config);
      const auto top = std::max_element(corr.begin(), corr.end());
      if (!(*top > best.score)) continue;
      const int i = int(top - corr.begin()), row = i / w, col = i % w;
      auto at = [&](int r, int c) { return corr[std::size_t(r) * w + c]; };
      const double fx = (col > 0 && col < w - 1) ? parabola_vertex(at(row, col - 1), *top, at(row, col + 1)) : 0;
      const double fz = (row > 0 && row < w - 1) ? parabola_vertex(at(row - 1, col), *top, at(row + 1, col)) : 0;
      best = {(col - m + fx) * config.cell_m, (row - m + fz) * config.cell_m, yaw, *top};
    }
  }
  best.score = std::max(best.score, 0.0);
  return best;
}

}  // namespace loopscan
