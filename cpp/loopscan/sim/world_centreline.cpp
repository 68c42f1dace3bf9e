#include "loopscan/sim/world_centreline.hpp"

#include <algorithm>
#include <cmath>

namespace loopscan::sim {
namespace {

double hdist(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::hypot(a.x() - b.x(), a.z() - b.z());
}

}  // namespace

std::vector<Eigen::Vector3d> densify_path(const std::vector<Eigen::Vector3d>& path, double min_gap,
                                          double max_step) {
  std::vector<Eigen::Vector3d> kept;
  for (const auto& p : path) {
    if (kept.empty() || hdist(p, kept.back()) >= min_gap) kept.push_back(p);
  }
  if (!path.empty() && hdist(path.back(), kept.back()) > 1e-9) kept.push_back(path.back());
  std::vector<Eigen::Vector3d> out;
  for (std::size_t i = 0; i < kept.size(); ++i) {
    if (i > 0) {
      const int n = static_cast<int>(std::ceil(hdist(kept[i - 1], kept[i]) / max_step));
      for (int k = 1; k < n; ++k)
        out.push_back(kept[i - 1] + (kept[i] - kept[i - 1]) * (static_cast<double>(k) / n));
    }
    out.push_back(kept[i]);
  }
  return out;
}

std::vector<Eigen::Vector3d> resample_path(const std::vector<Eigen::Vector3d>& path, double step) {
  std::vector<Eigen::Vector3d> out;
  if (path.empty()) return out;
  out.push_back(path.front());
  double next = step, travelled = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) {
    const double len = hdist(path[i - 1], path[i]);
    while (len > 0.0 && travelled + len >= next) {
      const double s = (next - travelled) / len;
      out.push_back(path[i - 1] + s * (path[i] - path[i - 1]));
      next += step;
    }
    travelled += len;
  }
  return out;
}

CentrelineIndex::CentrelineIndex(const std::vector<Eigen::Vector3d>& path, double cell_m)
    : cell_(cell_m) {
  const auto pts = densify_path(path, 0.5, 2.0);
  if (pts.empty()) return;
  for (std::size_t i = 0; i + 1 < pts.size(); ++i)
    segs_.push_back(
        {pts[i].x(), pts[i].z(), pts[i].y(), pts[i + 1].x(), pts[i + 1].z(), pts[i + 1].y()});
  if (segs_.empty())
    segs_.push_back({pts[0].x(), pts[0].z(), pts[0].y(), pts[0].x(), pts[0].z(), pts[0].y()});
  arc_start_.reserve(segs_.size());
  double arc = 0.0;
  for (const Segment& s : segs_) {
    arc_start_.push_back(arc);
    arc += std::hypot(s.bx - s.ax, s.bz - s.az);
  }
  double max_x = -1e300, max_z = -1e300;
  min_x_ = min_z_ = 1e300;
  min_y_ = 1e300;
  max_y_ = -1e300;
  for (const auto& p : pts) {
    min_x_ = std::min(min_x_, p.x());
    min_z_ = std::min(min_z_, p.z());
    max_x = std::max(max_x, p.x());
    max_z = std::max(max_z, p.z());
    min_y_ = std::min(min_y_, p.y());
    max_y_ = std::max(max_y_, p.y());
  }
  build_tree();
  nx_ = static_cast<int>(std::floor((max_x - min_x_) / cell_)) + 1;
  nz_ = static_cast<int>(std::floor((max_z - min_z_) / cell_)) + 1;
  // Two passes (count, fill) over segment bounding boxes give a compact, ordered CSR layout.
  std::vector<std::uint32_t> count(static_cast<std::size_t>(nx_) * nz_ + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1) {
      start_.assign(count.size(), 0);
      for (std::size_t c = 1; c < count.size(); ++c) start_[c] = start_[c - 1] + count[c - 1];
      items_.assign(start_.back(), 0);
      std::fill(count.begin(), count.end(), 0);
    }
    for (std::size_t s = 0; s < segs_.size(); ++s) {
      const Segment& g = segs_[s];
      const int i0 = cell_x(std::min(g.ax, g.bx)), i1 = cell_x(std::max(g.ax, g.bx));
      const int j0 = cell_z(std::min(g.az, g.bz)), j1 = cell_z(std::max(g.az, g.bz));
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) {
          const std::size_t c = static_cast<std::size_t>(j) * nx_ + i;
          if (pass == 1) items_[start_[c] + count[c]] = static_cast<std::uint32_t>(s);
          ++count[c];
        }
    }
  }
}

int CentrelineIndex::cell_x(double x) const {
  return std::clamp(static_cast<int>(std::floor((x - min_x_) / cell_)), 0, nx_ - 1);
}
int CentrelineIndex::cell_z(double z) const {
  return std::clamp(static_cast<int>(std::floor((z - min_z_) / cell_)), 0, nz_ - 1);
}

void CentrelineIndex::consider(std::uint32_t segment, double x, double z, Nearest& best) const {
  const Segment& s = segs_[segment];
  double t;
  const double d2 = distance2(s, x, z, t);
  if (d2 < best.distance * best.distance) {  // squared compare: no sqrt per segment
    best.distance = std::sqrt(d2);
    best.y = s.ay + t * (s.by - s.ay);
    best.found = true;
    best.segment = segment;
  }
}

double CentrelineIndex::arc_length(std::uint32_t segment, double x, double z) const {
  const Segment& s = segs_[segment];
  double t;
  distance2(s, x, z, t);
  return arc_start_[segment] + t * std::hypot(s.bx - s.ax, s.bz - s.az);
}

CentrelineIndex::Nearest CentrelineIndex::nearest_linear(double x, double z) const {
  Nearest best;
  for (std::uint32_t s = 0; s < segs_.size(); ++s) consider(s, x, z, best);
  return best;
}

CentrelineIndex::Nearest CentrelineIndex::nearest(double x, double z) const {
  Nearest best;
  if (segs_.empty()) return best;
  constexpr int kMaxRing = 16;
  const double fx = std::floor((x - min_x_) / cell_), fz = std::floor((z - min_z_) / cell_);
  if (fx < -kMaxRing || fz < -kMaxRing || fx >= nx_ + kMaxRing || fz >= nz_ + kMaxRing)
    return nearest_linear(x, z);  // far outside the street network: rare, exact anyway
  const int ci = static_cast<int>(fx), cj = static_cast<int>(fz);
  const auto visit = [&](int i, int j) {
    if (i < 0 || i >= nx_) return;
    const std::size_t c = static_cast<std::size_t>(j) * nx_ + i;
    for (std::uint32_t k = start_[c]; k < start_[c + 1]; ++k) consider(items_[k], x, z, best);
  };
  for (int r = 0; r <= kMaxRing; ++r) {
    for (int j = std::max(cj - r, 0); j <= std::min(cj + r, nz_ - 1); ++j) {
      if (j == cj - r || j == cj + r) {
        for (int i = ci - r; i <= ci + r; ++i) visit(i, j);
      } else {
        visit(ci - r, j);
        visit(ci + r, j);
      }
    }
    // Everything outside the (2r+1)^2 block is at least this far away.
    const double bound =
        std::min(std::min(x - (min_x_ + (ci - r) * cell_), min_x_ + (ci + r + 1) * cell_ - x),
                 std::min(z - (min_z_ + (cj - r) * cell_), min_z_ + (cj + r + 1) * cell_ - z));
    if (best.found && best.distance <= bound) return best;
  }
  return nearest_linear(x, z);
}

CentrelineIndex::Nearest CentrelineIndex::nearest_of(const std::vector<Candidate>& sorted,
                                                     double shift, double x, double z) const {
  Nearest best;
  double best_d2 = std::numeric_limits<double>::infinity();
  // Rounding margin of the distances (metres): only ever lets more candidates in.
  constexpr double kSlack = 1e-6;
  for (const Candidate& c : sorted) {
    if (c.distance - shift > best.distance + kSlack) break;
    const Segment& s = segs_[c.segment];
    double t;
    const double d2 = distance2(s, x, z, t);
    if (d2 < best_d2 || (d2 == best_d2 && c.segment < best.segment)) {
      best_d2 = d2;
      best.distance = std::sqrt(d2);
      best.y = s.ay + t * (s.by - s.ay);
      best.found = true;
      best.segment = c.segment;
    }
  }
  return best;
}

double CentrelineIndex::distance_to(const Footprint& f, double search) const {
  double best = std::numeric_limits<double>::infinity();
  if (segs_.empty()) return best;
  const Eigen::Vector4d b = footprint_bounds(f);
  const int i0 = cell_x(b[0] - search), i1 = cell_x(b[2] + search);
  const int j0 = cell_z(b[1] - search), j1 = cell_z(b[3] + search);
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) {
      const std::size_t c = static_cast<std::size_t>(j) * nx_ + i;
      for (std::uint32_t k = start_[c]; k < start_[c + 1]; ++k) {
        const Segment& s = segs_[items_[k]];
        best = std::min(best, footprint_segment_distance(f, s.ax, s.az, s.bx, s.bz));
      }
    }
  return best;
}

}  // namespace loopscan::sim
