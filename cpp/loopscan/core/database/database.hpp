#pragma once
// The online place database: places are added as keyframes arrive, and a query returns the k
// best matches with their relative yaw, by exact search or through an index and exact
// re-scoring of its candidates. Places carry their session, so one database serves several
// sessions (build from summer, query from winter). No I/O here: io/database_file saves it.
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "loopscan/core/config.hpp"
#include "loopscan/core/matching/birds_eye_match.hpp"
#include "loopscan/core/matching/fusion.hpp"
#include "loopscan/core/signature.hpp"

namespace loopscan {

struct PlaceRef {
  int session = 0;
  int keyframe = 0;
  bool operator==(const PlaceRef& o) const {
    return session == o.session && keyframe == o.keyframe;
  }
};

// A signature plus the descriptor's axes in the keyframe's camera frame (rows = axes, from
// describe()); only Scan Context uses the frame, to turn sector shifts into yaw.
struct PlaceDescriptor {
  Signature signature;
  Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();
};

// How a place's Scan Context spectra are kept: floats (exact), or one signed byte per value
// with a scale per ring (compact_spectra.hpp: ~2.9 KB a place instead of ~10 KB; distances
// change by the rounding only). M2DP and DELIGHT places are always full.
enum class PlaceStorage { Full, Compact };

// "full" | "compact"; throws std::invalid_argument otherwise.
PlaceStorage parse_storage(const std::string& name);
std::string storage_name(PlaceStorage storage);

struct DatabaseConfig {
  Method method = Method::ScanContext;
  // SC and M2DP: fused as in the paper, or one half alone. Ignored for DELIGHT.
  Fusion fusion = Fusion::Fused;
  double structure_weight = 2.0;  // w_s
  // Rings and sectors of the Scan Context signatures (sectors must be even); its other fields
  // are not used here.
  ScanContextConfig scan_context;
  // Bird's-eye places: their layout and the image search of the exact distance.
  BirdsEyePlaceConfig birds_eye;
  BirdsEyeSearchConfig birds_eye_search;
  // Columns of an M2DP or DELIGHT signature; 0: the default parameters' width.
  int columns = 0;
  PlaceStorage storage = PlaceStorage::Full;
  // How the places were described: the mode and the descriptor's frame. A map records them, so
  // that its queries and later sessions are described the same way; unknown (nullopt) for maps
  // saved before the database file recorded them.
  std::optional<Mode> mode;
  std::optional<DescriptorFrame> frame;
};

enum class Retrieval { Exact, Indexed };

// "indexed" | "exact"; throws std::invalid_argument otherwise.
Retrieval parse_retrieval(const std::string& name);
std::string retrieval_name(Retrieval retrieval);

struct QueryOptions {
  Retrieval retrieval = Retrieval::Indexed;
  // Indexed: places taken from the index (SC coarse key / M2DP KD-tree, DELIGHT coarse
  // histogram, the bird's-eye key) and scored exactly.
  int candidates = 50;
  // Scan Context: places the coarse stage (key_scan.hpp) hands to the spectral re-ranking, per
  // candidate.
  int index_pool_factor = 8;
  // Fused scores are z-scores of each half over the row of eligible places (Matlab's
  // normalize, as offline). Exact search has the whole row; indexed search estimates its mean
  // and standard deviation from this many eligible places spread evenly over the database.
  int stats_sample = 64;
  int exclude_recent = 0;     // ignore the N places added last (same-session loop closure)
  std::vector<int> sessions;  // only places of these sessions; empty: all
  // Any further rule (insertion index, place) -> may match; empty: all places may.
  std::function<bool(std::size_t, const PlaceRef&)> accept;
  double max_distance = std::numeric_limits<double>::infinity();
  // Uniqueness: with g = (row mean - distance), the best result is kept only if the best
  // distinct place after it has g_second <= ratio * g_best. 1 disables the test. A place is
  // distinct from the best when it is in another session or more than `distinct_gap`
  // keyframes away. A query that fails returns no results.
  double uniqueness_ratio = 1.0;
  int distinct_gap = 50;
  // Scan Context with lateral versions: indexed candidates are first scored with only the
  // query versions whose index search proposed them; the best `refine` (at least k) are then
  // scored with every version. 0: every candidate with every version.
  int refine = 8;
  // Threads scoring the places of an exact search (1: the caller's thread only).
  int threads = 1;
};

struct Candidate {
  PlaceRef place;
  std::size_t index = 0;  // insertion order in the database
  double distance = 0;    // fused z-score or raw distance (see DatabaseConfig::fusion)
  // Scan Context: the database keyframe's heading in the query keyframe's camera frame, about
  // the camera's up axis (-y, KITTI/DSO convention), positive to the left, in (-pi, pi].
  // Bird's-eye places: from the image search. NaN for M2DP and DELIGHT.
  double yaw_rad = std::numeric_limits<double>::quiet_NaN();
  bool mirrored = false;  // Scan Context matched in mirrored sector order
  // Bird's-eye places: the database keyframe's position on the query keyframe's ground plane
  // (camera x right, z forward, m). NaN for the other methods.
  double x_m = std::numeric_limits<double>::quiet_NaN();
  double z_m = std::numeric_limits<double>::quiet_NaN();
};

class PlaceStore;

// query() is const and may run on several threads at once; add() must not overlap anything.
class Database {
 public:
  // Throws std::invalid_argument on an invalid config (see database_checks.hpp).
  explicit Database(const DatabaseConfig& config = {});
  ~Database();
  Database(Database&&) noexcept;
  Database& operator=(Database&&) noexcept;

  // Throws std::invalid_argument when the signature does not have the method's shape or holds
  // NaN / infinite values, or the frame or pose does.
  void add(const PlaceRef& place, const PlaceDescriptor& descriptor,
           const std::optional<Pose3x4>& T_cam_world = std::nullopt);

  // Up to k results, best first. Throws std::invalid_argument on invalid options or a
  // non-finite query signature.
  std::vector<Candidate> query(const PlaceDescriptor& descriptor, int k,
                               const QueryOptions& options = {}) const;

  std::size_t size() const { return places_.size(); }
  const DatabaseConfig& config() const { return config_; }
  // Bird's-eye places: how later queries search their finalists' images (a query-time setting,
  // not saved with the map). Throws std::invalid_argument on a search these places cannot run.
  void set_birds_eye_search(const BirdsEyeSearchConfig& search);
  PlaceRef place(std::size_t i) const { return places_[i]; }
  std::optional<Pose3x4> pose(std::size_t i) const;
  const Eigen::Matrix3f& frame(std::size_t i) const { return frames_[i]; }

  // The stored form of a place (what persistence writes): a fixed-length float payload.
  int payload_floats() const;
  void stored_payload(std::size_t i, float* out) const;  // payload_floats() values
  // Appends a place from its stored form (the loader's path; no re-encoding).
  void add_stored(const PlaceRef& place, const float* payload, const Eigen::Matrix3f& frame,
                  const std::optional<Pose3x4>& T_cam_world);

  // Heap bytes held by the database (payloads, index, metadata).
  std::size_t memory_bytes() const;

 private:
  DatabaseConfig config_;
  std::unique_ptr<PlaceStore> store_;  // owns the payloads, so the index may point into them
  std::vector<PlaceRef> places_;
  std::vector<Eigen::Matrix3f> frames_;
  std::vector<std::int32_t> pose_slot_;  // -1: no pose; else an index into pose_values_
  std::vector<Pose3x4> pose_values_;
};

// An `accept` rule for querying a database with its own sequence, like the offline
// same-session protocol: places whose index differs from `index` by less than `width` may not
// match.
std::function<bool(std::size_t, const PlaceRef&)> outside_band(std::size_t index,
                                                               std::size_t width);

// The yaw of Candidate::yaw_rad from a sector alignment and the two descriptor frames.
double relative_yaw(const Eigen::Matrix3d& query_frame, const Eigen::Matrix3d& place_frame,
                    int shift, bool mirrored, int sectors);

}  // namespace loopscan
