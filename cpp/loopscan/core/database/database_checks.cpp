#include "loopscan/core/database/database_checks.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace loopscan {
namespace {

constexpr double kMaxValue = 1e30;

void need(bool ok, const char* who, const std::string& what) {
  if (!ok) throw std::invalid_argument(std::string(who) + ": " + what);
}

bool in(double v, double lo, double hi) { return v >= lo && v <= hi; }  // false for NaN

}  // namespace

void validate(const DatabaseConfig& c) {
  need(in(c.structure_weight, 0.0, 1000.0), "DatabaseConfig",
       "structure_weight must be finite and in [0, 1000] (got " +
           std::to_string(c.structure_weight) + ")");
  if (c.method == Method::ScanContext) validate(c.scan_context);
  need(c.fusion != Fusion::Adaptive, "DatabaseConfig",
       "adaptive fusion weighs a whole set of queries at once (evaluate); a database fuses "
       "each query on its own: use fused, structure or intensity");
  need(c.columns >= 0 && c.columns <= (1 << 20), "DatabaseConfig", "columns must be in [0, 2^20]");
  need(c.storage == PlaceStorage::Full || c.method == Method::ScanContext, "DatabaseConfig",
       "compact storage is for Scan Context places (M2DP and DELIGHT places are already small)");
}

void require_same_description(const DatabaseConfig& map, const DatabaseConfig& own,
                              const char* who) {
  need(map.method == own.method, who,
       "the map holds " + method_name(map.method) + " places, this describes with " +
           method_name(own.method));
  need(!map.mode || !own.mode || *map.mode == *own.mode, who,
       "the map's places were described in " + (map.mode ? mode_name(*map.mode) : "") +
           " mode, this describes in " + (own.mode ? mode_name(*own.mode) : "") + " mode");
  need(!map.frame || !own.frame || *map.frame == *own.frame, who,
       "the map's places were described in the " +
           (map.frame ? descriptor_frame_name(*map.frame) : "") + " frame, this describes in the " +
           (own.frame ? descriptor_frame_name(*own.frame) : "") + " frame");
  need(map.method != Method::BirdsEye || same_layout(map.birds_eye, own.birds_eye), who,
       "the map's bird's-eye places have another layout (cell kind, cell_m, range_m, "
       "taper_start_m, taper_end_m, rings, angles) than this describes");
}

void validate(const QueryOptions& o, int k) {
  const char* who = "Database::query";
  need(k >= 0 && k <= 1000000, who, "k must be in [0, 1000000] (got " + std::to_string(k) + ")");
  need(o.candidates >= 1 && o.candidates <= 1000000, who, "candidates must be in [1, 1000000]");
  need(o.index_pool_factor >= 1 && o.index_pool_factor <= 1000, who,
       "index_pool_factor must be in [1, 1000]");
  need(o.stats_sample >= 2 && o.stats_sample <= 1000000, who,
       "stats_sample must be in [2, 1000000]");
  need(o.exclude_recent >= 0, who, "exclude_recent must be >= 0");
  need(o.refine >= 0 && o.refine <= 1000000, who, "refine must be in [0, 1000000]");
  need(in(o.uniqueness_ratio, 0.0, 1.0), who, "uniqueness_ratio must be in [0, 1]");
  need(!std::isnan(o.max_distance), who, "max_distance must not be NaN");
  need(o.distinct_gap >= 0, who, "distinct_gap must be >= 0");
  need(o.threads >= 1 && o.threads <= 1024, who, "threads must be in [1, 1024]");
}

// The message is built only on failure: queries check thousands of values each.
void require_finite_values(const float* values, std::size_t n, const char* who) {
  for (std::size_t i = 0; i < n; ++i) {
    if (!(std::abs(values[i]) <= kMaxValue)) {
      need(false, who, "value " + std::to_string(i) + " is NaN, infinite or beyond +-1e30");
    }
  }
}

void require_finite_values(const Signature& s, const char* who) {
  for (Eigen::Index i = 0; i < s.size(); ++i) {
    if (!(std::abs(s.data()[i]) <= kMaxValue)) {
      need(false, who,
           "signature value " + std::to_string(i) + " is NaN, infinite or beyond +-1e30");
    }
  }
}

void require_finite_frame_and_pose(const Eigen::Matrix3f& frame,
                                   const std::optional<Pose3x4>& T_cam_world, const char* who) {
  need(frame.allFinite(), who, "the descriptor frame has a NaN or infinite entry");
  need(!T_cam_world || T_cam_world->allFinite(), who, "the pose has a NaN or infinite entry");
}

}  // namespace loopscan
