#include "loopscan/core/database/database.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/LU>

#include "loopscan/core/database/database_checks.hpp"
#include "loopscan/core/database/place_store.hpp"
#include "loopscan/core/parallel.hpp"
#include "loopscan/core/yaw.hpp"

namespace loopscan {
namespace {

std::unique_ptr<PlaceStore> make_store(const DatabaseConfig& c) {
  const int columns = c.columns > 0 ? c.columns : signature_columns(c.method);
  switch (c.method) {
    case Method::ScanContext:
      return make_scan_context_store(c.scan_context, c.storage);
    case Method::M2dp:
      return make_m2dp_store(columns);
    case Method::Delight:
      return make_delight_store(columns);
    case Method::BirdsEye:
      return make_birds_eye_store(c.birds_eye, c.birds_eye_search);
  }
  throw std::invalid_argument("unknown method");
}

// Mean and standard deviation (n - 1) of one component over a set of rows.
struct RowStats {
  double mean = 0, stddev = 0;
};

RowStats stats_of(const std::vector<double>& raw, int components, int c) {
  const std::size_t n = raw.size() / components;
  RowStats s;
  if (n == 0) return s;
  for (std::size_t j = 0; j < n; ++j) s.mean += raw[j * components + c];
  s.mean /= static_cast<double>(n);
  double ss = 0;
  for (std::size_t j = 0; j < n; ++j) ss += std::pow(raw[j * components + c] - s.mean, 2);
  s.stddev = n > 1 ? std::sqrt(ss / static_cast<double>(n - 1)) : 0.0;
  return s;
}

double zscore(double x, const RowStats& s) { return s.stddev > 0 ? (x - s.mean) / s.stddev : 0.0; }

// `want` eligible places among the first `limit`, spread evenly over them (or the first ones
// when filters leave few eligible places).
std::vector<std::size_t> stats_sample(const Eligible& eligible, std::size_t limit, int wanted) {
  std::vector<std::size_t> sample;
  const std::size_t want = static_cast<std::size_t>(std::max(2, wanted));
  const std::size_t step = std::max<std::size_t>(1, limit / want);
  for (std::size_t i = 0; i < limit && sample.size() < want; i += step) {
    if (eligible(i)) sample.push_back(i);
  }
  if (sample.size() < want / 2) {
    sample.clear();
    for (std::size_t i = 0; i < limit && sample.size() < want; ++i) {
      if (eligible(i)) sample.push_back(i);
    }
  }
  return sample;
}

}  // namespace

PlaceStorage parse_storage(const std::string& name) {
  if (name == "full") return PlaceStorage::Full;
  if (name == "compact") return PlaceStorage::Compact;
  throw std::invalid_argument("storage: expected 'full' or 'compact', got '" + name + "'");
}

std::string storage_name(PlaceStorage storage) {
  return storage == PlaceStorage::Compact ? "compact" : "full";
}

Retrieval parse_retrieval(const std::string& name) {
  if (name == "indexed") return Retrieval::Indexed;
  if (name == "exact") return Retrieval::Exact;
  throw std::invalid_argument("retrieval: expected 'indexed' or 'exact', got '" + name + "'");
}

std::string retrieval_name(Retrieval retrieval) {
  return retrieval == Retrieval::Exact ? "exact" : "indexed";
}

Database::Database(const DatabaseConfig& config)
    : config_(config), store_((validate(config), make_store(config))) {}
Database::~Database() = default;
Database::Database(Database&&) noexcept = default;

void Database::set_birds_eye_search(const BirdsEyeSearchConfig& search) {
  store_->set_birds_eye_search(search);
  config_.birds_eye_search = search;
}
Database& Database::operator=(Database&&) noexcept = default;

int Database::payload_floats() const { return store_->payload_floats(); }

void Database::stored_payload(std::size_t i, float* out) const { store_->stored(i, out); }

void Database::add(const PlaceRef& place, const PlaceDescriptor& descriptor,
                   const std::optional<Pose3x4>& T_cam_world) {
  require_finite_values(descriptor.signature, "Database::add");
  std::vector<float> payload(store_->payload_floats());
  store_->encode(descriptor.signature, payload.data());
  add_stored(place, payload.data(), descriptor.frame.cast<float>(), T_cam_world);
}

void Database::add_stored(const PlaceRef& place, const float* payload, const Eigen::Matrix3f& frame,
                          const std::optional<Pose3x4>& T_cam_world) {
  require_finite_values(payload, static_cast<std::size_t>(store_->value_floats()),
                        "Database::add_stored");
  require_finite_frame_and_pose(frame, T_cam_world, "Database::add");
  store_->append(payload);
  places_.push_back(place);
  frames_.push_back(frame);
  pose_slot_.push_back(T_cam_world ? static_cast<std::int32_t>(pose_values_.size()) : -1);
  if (T_cam_world) pose_values_.push_back(*T_cam_world);
  store_->indexed_up_to(places_.size());
}

std::vector<Candidate> Database::query(const PlaceDescriptor& descriptor, int k,
                                       const QueryOptions& options) const {
  validate(options, k);
  require_finite_values(descriptor.signature, "Database::query");
  const auto query = store_->prepare(descriptor.signature);  // validates the shape
  const std::size_t n = places_.size();
  const std::size_t limit =
      n - std::min<std::size_t>(n, static_cast<std::size_t>(std::max(0, options.exclude_recent)));
  const std::vector<int>& sessions = options.sessions;
  const Eligible eligible = [&](std::size_t i) {
    return i < limit &&
           (sessions.empty() ||
            std::find(sessions.begin(), sessions.end(), places_[i].session) != sessions.end()) &&
           (!options.accept || options.accept(i, places_[i]));
  };
  if (k <= 0 || limit == 0) return {};

  // The places scored exactly: all eligible ones, or the index's candidates.
  std::vector<std::size_t> scored;
  const bool exact = options.retrieval == Retrieval::Exact;
  if (store_->finalists() > 0) {
    // Bird's-eye places: the key's finalists, whichever the retrieval (the distance's definition).
    store_->candidates(*query, store_->finalists(), 0, eligible, n, scored);
  } else if (exact) {
    for (std::size_t i = 0; i < limit; ++i) {
      if (eligible(i)) scored.push_back(i);
    }
  } else {
    const auto count = static_cast<std::size_t>(std::max(1, options.candidates));
    const auto pool = count * static_cast<std::size_t>(std::max(1, options.index_pool_factor));
    store_->candidates(*query, count, pool, eligible, n, scored);
  }
  if (scored.empty()) return {};
  const int C = store_->components();

  // Row statistics: the whole eligible row (exact: computed below from the scores), or a
  // sample of it spread over the database.
  const bool fused = C == 2 && config_.fusion == Fusion::Fused;
  const bool need_stats = fused || options.uniqueness_ratio < 1.0;
  RowStats stats[2];
  if (need_stats && !exact) {
    const std::vector<std::size_t> sample = stats_sample(eligible, limit, options.stats_sample);
    std::vector<double> sample_raw(sample.size() * C);
    for (std::size_t j = 0; j < sample.size(); ++j) {
      store_->distances(*query, store_->record(sample[j]), &sample_raw[j * C]);
    }
    for (int c = 0; c < C; ++c) stats[c] = stats_of(sample_raw, C, c);
  }

  std::vector<double> raw(scored.size() * C);
  const bool first_pass = !exact && options.refine > 0 && store_->partial_first_pass(*query);
  if (exact) {
    // Many places may be scored on several threads (results identical: each place's
    // distances are computed the same way whichever thread does it).
    const int threads = scored.size() >= 256 ? options.threads : 1;
    for_each_index(scored.size(), threads, [&](std::size_t j) {
      store_->distances(*query, store_->record(scored[j]), &raw[j * C]);
    });
    if (need_stats) {
      for (int c = 0; c < C; ++c) stats[c] = stats_of(raw, C, c);
    }
  } else {
    for (std::size_t j = 0; j < scored.size(); ++j) {
      if (first_pass) {
        store_->first_pass(*query, j, store_->record(scored[j]), &raw[j * C]);
      } else {
        store_->distances(*query, store_->record(scored[j]), &raw[j * C]);
      }
    }
  }

  // One distance per scored place, and the row mean on the same scale.
  const int part = config_.fusion == Fusion::Intensity && C == 2 ? 1 : 0;
  auto distance_of = [&](const double* d) {
    return fused ? config_.structure_weight * zscore(d[0], stats[0]) + zscore(d[1], stats[1])
                 : d[part];
  };
  std::vector<Candidate> ranked(scored.size());
  for (std::size_t j = 0; j < scored.size(); ++j) {
    Candidate& c = ranked[j];
    c.index = scored[j];
    c.place = places_[scored[j]];
    c.distance = distance_of(&raw[j * C]);
  }
  auto better = [](const Candidate& a, const Candidate& b) {
    return a.distance < b.distance || (a.distance == b.distance && a.index < b.index);
  };
  if (first_pass) {
    // The first pass bounds every distance from above; the best few get their exact one.
    const std::size_t n_refine =
        std::min(ranked.size(), static_cast<std::size_t>(std::max(options.refine, k)));
    std::partial_sort(ranked.begin(), ranked.begin() + n_refine, ranked.end(), better);
    double d[2];
    for (std::size_t j = 0; j < n_refine; ++j) {
      store_->distances(*query, store_->record(ranked[j].index), d);
      ranked[j].distance = distance_of(d);
    }
  }
  const double row_mean = fused ? 0.0 : stats[part].mean;
  // Only the head of the ranking is needed: the k results, and for the uniqueness test the
  // best distinct place, almost always among the first few dozen (else sort it all).
  std::size_t head = std::min(ranked.size(), static_cast<std::size_t>(k) + 64);
  std::partial_sort(ranked.begin(), ranked.begin() + head, ranked.end(), better);

  if (options.uniqueness_ratio < 1.0) {
    for (std::size_t j = 1; j < ranked.size(); ++j) {
      if (j == head) {
        std::sort(ranked.begin() + head, ranked.end(), better);
        head = ranked.size();
      }
      const Candidate& best = ranked.front();
      const PlaceRef& p = ranked[j].place;
      const bool distinct = p.session != best.place.session ||
                            std::abs(p.keyframe - best.place.keyframe) > options.distinct_gap;
      if (!distinct) continue;
      const double g_best = row_mean - best.distance, g_second = row_mean - ranked[j].distance;
      if (!(g_second <= options.uniqueness_ratio * g_best)) return {};
      break;
    }
  }

  std::vector<Candidate> out;
  for (std::size_t j = 0; j < head; ++j) {
    const Candidate& c = ranked[j];
    if (static_cast<int>(out.size()) == k || c.distance > options.max_distance) break;
    out.push_back(c);
  }
  for (Candidate& c : out) {
    const float* record = store_->record(c.index);
    if (const auto a = store_->align(*query, record)) {
      c.mirrored = a->mirrored;
      c.yaw_rad = relative_yaw(descriptor.frame, frames_[c.index].cast<double>(), a->shift,
                               a->mirrored, store_->sectors());
    } else if (const auto pose = store_->ground_pose(*query, record)) {
      c.yaw_rad = pose->yaw_rad;
      c.x_m = pose->x_m;
      c.z_m = pose->z_m;
    }
  }
  return out;
}

std::size_t Database::memory_bytes() const {
  return store_->memory_bytes() + places_.capacity() * sizeof(PlaceRef) +
         frames_.capacity() * sizeof(Eigen::Matrix3f) +
         pose_slot_.capacity() * sizeof(std::int32_t) + pose_values_.capacity() * sizeof(Pose3x4);
}

std::optional<Pose3x4> Database::pose(std::size_t i) const {
  if (pose_slot_[i] < 0) return std::nullopt;
  return pose_values_[static_cast<std::size_t>(pose_slot_[i])];
}

std::function<bool(std::size_t, const PlaceRef&)> outside_band(std::size_t index,
                                                               std::size_t width) {
  return [index, width](std::size_t j, const PlaceRef&) {
    return (index > j ? index - j : j - index) >= width;
  };
}

double relative_yaw(const Eigen::Matrix3d& query_frame, const Eigen::Matrix3d& place_frame,
                    int shift, bool mirrored, int sectors) {
  // Descriptor coordinates a = B p (B = frame). A match maps the query's descriptor plane
  // (axes 1, 2) to the place's by a rotation of shift sectors, or by a reflection when
  // mirrored (bin centres: angle -> (shift + 1) * width - angle); the up axis keeps or flips
  // its sign so the whole map is a proper rotation. Then p_place = B_p^T G B_q p_query.
  const double width = 2.0 * M_PI / sectors;
  Eigen::Matrix3d G = Eigen::Matrix3d::Zero();
  if (mirrored) {
    const double c = (shift + 1) * width;
    G.block<2, 2>(1, 1) << std::cos(c), std::sin(c), std::sin(c), -std::cos(c);
  } else {
    const double c = shift * width;
    G.block<2, 2>(1, 1) << std::cos(c), -std::sin(c), std::sin(c), std::cos(c);
  }
  const double det =
      G.block<2, 2>(1, 1).determinant() * query_frame.determinant() * place_frame.determinant();
  G(0, 0) = det < 0 ? -1.0 : 1.0;
  // The place keyframe's orientation in the query camera frame.
  const Eigen::Matrix3d R_query_place = (place_frame.transpose() * G * query_frame).transpose();
  return yaw_of(R_query_place);
}

}  // namespace loopscan
