#include "loopscan/core/matching/pair_distance.hpp"

#include <algorithm>
#include <limits>

namespace loopscan {
namespace {

Eigen::VectorXd half_of(const Signature& s, Component part, Eigen::Index row = 0) {
  const Eigen::Index half = s.cols() / 2;
  return s.row(row).segment(part == Component::Structure ? 0 : half, half).transpose();
}

Eigen::VectorXd normalized(Eigen::VectorXd v) {
  const double n = v.norm();
  return n > 0 ? Eigen::VectorXd(v / n) : Eigen::VectorXd(Eigen::VectorXd::Zero(v.size()));
}

}  // namespace

double scan_context_distance(const Signature& query, const Signature& db, Component part,
                             const ScanContextConfig& config, int* best_shift, bool* mirrored) {
  const int rings = config.rings, sectors = config.sectors;
  const Eigen::VectorXd d = normalized(half_of(db, part));
  double best = -std::numeric_limits<double>::infinity();
  for (Eigen::Index version = 0; version < query.rows(); ++version) {
    const Eigen::VectorXd q = normalized(half_of(query, part, version));
    for (int shift = 0; shift < sectors; ++shift) {
      for (int mirror = 0; mirror < 2; ++mirror) {
        double dot = 0;
        for (int s = 0; s < sectors; ++s) {
          const int from =
              mirror ? ((shift - s) % sectors + sectors) % sectors : (s + shift) % sectors;
          for (int r = 0; r < rings; ++r) dot += q(from * rings + r) * d(s * rings + r);
        }
        if (dot > best) {
          best = dot;
          if (best_shift) *best_shift = shift;
          if (mirrored) *mirrored = mirror == 1;
        }
      }
    }
  }
  return (1.0 - best) / 2.0;
}

double m2dp_distance(const Signature& query, const Signature& db, Component part) {
  const Eigen::Index half = query.cols() / 2;
  const Eigen::Index offset = part == Component::Structure ? 0 : half;
  double best = std::numeric_limits<double>::infinity();
  for (Eigen::Index i = 0; i < query.rows(); ++i) {
    for (Eigen::Index j = 0; j < db.rows(); ++j) {
      const double dot = query.row(i).segment(offset, half).dot(db.row(j).segment(offset, half));
      best = std::min(best, (1.0 - dot) / 2.0);
    }
  }
  return best;
}

double delight_distance(const Signature& query, const Signature& db) {
  double best = std::numeric_limits<double>::infinity();
  for (int mask : kDelightRegionMasks) {
    double sum = 0;
    long used = 0;
    for (Eigen::Index bin = 0; bin < query.cols(); ++bin) {
      for (int r = 0; r < 16; ++r) {
        const double a = query(r, bin), b = db(r ^ mask, bin);
        if (a + b > 0) {
          sum += 2 * (a - b) * (a - b) / (a + b);
          ++used;
        }
      }
    }
    best = std::min(best, used > 0 ? sum / used : 0.0);
  }
  return best;
}

}  // namespace loopscan
