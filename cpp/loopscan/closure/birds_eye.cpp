#include "loopscan/closure/birds_eye.hpp"

#include "loopscan/core/peak_vertex.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace loopscan::closure {
namespace {

int shift_cells(const BirdsEyeConfig& c) { return int(std::ceil(c.max_shift_m / c.cell_m)); }

struct Peak {
  double score;
  Eigen::Isometry3d T;
};

}  // namespace

bool within_ground_range(const Eigen::Vector3f& p, double range_m) {
  return double(p.x()) * p.x() + double(p.z()) * p.z() <= range_m * range_m;
}

void validate(const BirdsEyeConfig& c) {
  const auto fail = [](const char* what) {
    throw std::invalid_argument(std::string("birds-eye config: ") + what);
  };
  if (!(c.cell_m >= 0.1 && c.cell_m <= 10)) fail("cell_m in [0.1, 10]");
  if (!(c.max_range_m > 0 && c.max_range_m <= 200)) fail("max_range_m in (0, 200]");
  if (!(c.max_shift_m >= 0 && c.max_shift_m <= 50)) fail("max_shift_m in [0, 50]");
  if (!(c.max_range_m / c.cell_m <= 1000)) fail("max_range_m / cell_m at most 1000");
  if (!(c.yaw_window_deg >= 0 && c.yaw_window_deg <= 180)) fail("yaw_window_deg in [0, 180]");
  if (!(c.yaw_step_deg >= 0.1 && c.yaw_step_deg <= 90)) fail("yaw_step_deg in [0.1, 90]");
  if (c.peaks < 1 || c.peaks > 100) fail("peaks in [1, 100]");
  if (!(c.separation_m >= 0 && c.separation_m <= 100)) fail("separation_m in [0, 100]");
  if (!(c.separation_deg >= 0 && c.separation_deg <= 180)) fail("separation_deg in [0, 180]");
}

BirdsEyeGrid::BirdsEyeGrid(const PlaceCloud& query, const BirdsEyeConfig& config) : config_(config) {
  validate(config);
  // Wide enough that every shift of every place cell that can meet a query cell stays inside.
  centre_ = int(std::ceil(config.max_range_m / config.cell_m)) + 2 * shift_cells(config) + 2;
  n_ = 2 * centre_ + 1;
  std::vector<float> count(std::size_t(n_) * std::size_t(n_), 0.0f);
  for (std::size_t i = 0; i < query.structure && i < query.points.size(); ++i) {
    const Eigen::Vector3f& p = query.points[i];
    if (!p.allFinite() || !within_ground_range(p, config.max_range_m)) continue;
    const Eigen::Vector2i c = cell(p.x(), p.z());
    count[std::size_t(c.x()) * std::size_t(n_) + std::size_t(c.y())] += 1.0f;
  }
  for (float& v : count) v = std::sqrt(v);
  // A [1 2 1] / 4 blur along rows, then along columns: a point a cell off still scores half.
  std::vector<float> rows(count.size(), 0.0f);
  density_.assign(count.size(), 0.0f);
  const auto at = [this](std::vector<float>& g, int r, int c) -> float& {
    return g[std::size_t(r) * std::size_t(n_) + std::size_t(c)];
  };
  for (int r = 0; r < n_; ++r) {
    for (int c = 1; c + 1 < n_; ++c) {
      at(rows, r, c) = 0.25f * at(count, r, c - 1) + 0.5f * at(count, r, c) + 0.25f * at(count, r, c + 1);
    }
  }
  for (int r = 1; r + 1 < n_; ++r) {
    for (int c = 0; c < n_; ++c) {
      at(density_, r, c) = 0.25f * at(rows, r - 1, c) + 0.5f * at(rows, r, c) + 0.25f * at(rows, r + 1, c);
    }
  }
}

Eigen::Vector2i BirdsEyeGrid::cell(float x, float z) const {
  const double inv = 1.0 / config_.cell_m;
  return {int(std::lround(double(z) * inv)) + centre_, int(std::lround(double(x) * inv)) + centre_};
}

std::vector<BirdsEyePose> birds_eye_search(const BirdsEyeGrid& query, const PlaceCloud& place,
                                           const std::vector<Eigen::Isometry3d>& guesses) {
  const BirdsEyeConfig& config = query.config();
  const int s = shift_cells(config), w = 2 * s + 1, n = query.size();
  Points3f structure;
  for (std::size_t i = 0; i < place.structure && i < place.points.size(); ++i) {
    const Eigen::Vector3f& p = place.points[i];
    if (p.allFinite() && within_ground_range(p, config.max_range_m)) structure.push_back(p);
  }
  if (structure.empty()) return {};
  const int half_yaws = int(std::floor(config.yaw_window_deg / config.yaw_step_deg + 1e-9));
  std::vector<float> weight(std::size_t(n) * std::size_t(n), 0.0f);  // the place's cells, reset per yaw
  std::vector<int> touched;
  std::vector<float> score(std::size_t(w) * std::size_t(w));
  std::vector<Peak> peaks;
  for (const Eigen::Isometry3d& guess : guesses) {
    for (int k = -half_yaws; k <= half_yaws; ++k) {
      const Eigen::Isometry3d T =
          yaw_rotation(k * config.yaw_step_deg * M_PI / 180.0) * guess;
      const Eigen::Matrix3f R = T.linear().cast<float>();
      const Eigen::Vector3f t = T.translation().cast<float>();
      touched.clear();
      for (const Eigen::Vector3f& p : structure) {
        const Eigen::Vector3f q = R * p + t;
        const Eigen::Vector2i c = query.cell(q.x(), q.z());
        if (c.x() < s || c.y() < s || c.x() + s >= n || c.y() + s >= n) continue;  // meets no query cell
        const int index = c.x() * n + c.y();
        if (weight[std::size_t(index)] == 0.0f) touched.push_back(index);
        weight[std::size_t(index)] += 1.0f;
      }
      std::fill(score.begin(), score.end(), 0.0f);
      for (int index : touched) {
        const float v = std::sqrt(weight[std::size_t(index)]);
        weight[std::size_t(index)] = 0.0f;
        const int row = index / n, col = index % n;
        for (int dr = -s; dr <= s; ++dr) {
          float* out = &score[std::size_t(dr + s) * std::size_t(w)];
          for (int dc = 0; dc < w; ++dc) out[dc] += v * query.at(row + dr, col - s + dc);
        }
      }
      const auto at = [&](int r, int c) { return double(score[std::size_t(r) * std::size_t(w) + std::size_t(c)]); };
      for (int r = 0; r < w; ++r) {
        for (int c = 0; c < w; ++c) {
          const double v = at(r, c);
          if (!(v > 0)) continue;
          bool maximum = true;
          for (int dr = -1; dr <= 1 && maximum; ++dr) {
            for (int dc = -1; dc <= 1; ++dc) {
              const int rr = r + dr, cc = c + dc;
              if ((dr || dc) && rr >= 0 && cc >= 0 && rr < w && cc < w &&
                  (at(rr, cc) > v || (at(rr, cc) == v && rr * w + cc < r * w + c))) {
                maximum = false;
                break;
              }
            }
          }
          if (!maximum) continue;
          const double dz = r > 0 && r + 1 < w ? parabola_vertex(at(r - 1, c), v, at(r + 1, c)) : 0.0;
          const double dx = c > 0 && c + 1 < w ? parabola_vertex(at(r, c - 1), v, at(r, c + 1)) : 0.0;
          Eigen::Isometry3d shifted = T;
          shifted.translation() +=
              Eigen::Vector3d((c - s + dx) * config.cell_m, 0.0, (r - s + dz) * config.cell_m);
          peaks.push_back({v, shifted});
        }
      }
    }
  }
  std::stable_sort(peaks.begin(), peaks.end(), [](const Peak& a, const Peak& b) { return a.score > b.score; });
  std::vector<BirdsEyePose> out;
  for (const Peak& p : peaks) {
    bool distinct = true;
    for (const BirdsEyePose& o : out) {
      const double dt = (p.T.translation() - o.T_query_place.translation()).norm();
      const double dyaw = std::abs(std::remainder(yaw_of(p.T) - yaw_of(o.T_query_place), 2 * M_PI));
      distinct &= dt > config.separation_m || dyaw > config.separation_deg * M_PI / 180.0;
    }
    if (!distinct) continue;
    out.push_back({p.T, p.score});
    if (int(out.size()) == config.peaks) break;
  }
  return out;
}

}  // namespace loopscan::closure
