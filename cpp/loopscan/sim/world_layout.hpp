#pragma once
// Internal helpers of the street layout (world_layout.cpp), shared with world_cars.cpp.
#include <cstdint>
#include <random>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

#include "loopscan/sim/world_objects.hpp"

namespace loopscan::sim {

// Uniform draw from the raw mt19937 output (portable: no library-specific distributions).
inline double uniform(std::mt19937& rng, double a, double b) {
  return a + (b - a) * (static_cast<double>(rng()) * (1.0 / 4294967296.0));
}
inline bool chance(std::mt19937& rng, double p) { return uniform(rng, 0.0, 1.0) < p; }

// A stretch of street visited for the first time: consecutive used centreline samples.
struct Run {
  std::vector<Eigen::Vector2d> pts;  // (x, z)
  std::vector<double> arc;           // cumulative length at each point
  double length() const { return arc.empty() ? 0.0 : arc.back(); }
  // Position and unit direction at arc length s (linear extrapolation beyond the ends).
  Eigen::Vector2d point_at(double s) const;
  Eigen::Vector2d tangent_at(double s) const;
};

// Samples the centreline every sample_spacing_m; a sample within revisit_radius_m of an
// already used sample (one further back along the path than the radius plus one spacing)
// is a revisit and ignored. Runs are the maximal sequences of used samples.
std::vector<Run> street_runs(const std::vector<Eigen::Vector3d>& centreline,
                             const WorldConfig& config, std::size_t& samples, std::size_t& used);

enum FootprintTag : int {
  kTagFacade = 1,
  kTagTrunk = 2,
  kTagCrown = 4,
  kTagPole = 8,
  kTagSlot = 16,
  kTagRail = 32
};

// Footprints placed so far, hashed by cell, to keep objects from overlapping each other.
class FootprintHash {
 public:
  explicit FootprintHash(double cell) : cell_(cell) {}
  void insert(const Footprint& f, int tag);
  bool overlaps(const Footprint& f, double margin, int tag_mask) const;

 private:
  // Both indices as 32-bit patterns side by side (shifting a negative int64 would be UB).
  std::uint64_t key(int i, int j) const {
    return (std::uint64_t{static_cast<std::uint32_t>(i)} << 32) | static_cast<std::uint32_t>(j);
  }
  double cell_;
  std::vector<std::pair<Footprint, int>> entries_;
  std::unordered_map<std::uint64_t, std::vector<int>> cells_;  // lookups only: order-free
};

struct Layout {
  StaticWorld& world;
  const std::vector<Run>& runs;
  FootprintHash occupied;
  int next_id = 0;
  // Offset (metres, signed by side) of the street's cross-section lines.
  Eigen::Vector2d beside(const Run& run, double s, double side, double offset) const;
  bool clear_of_road(const Footprint& f) const;
};

void place_facades(Layout& layout, std::mt19937& rng);
// Guard rails (WorldConfig::guard_rails) in 8 m pieces beside both road edges.
void place_guard_rails(Layout& layout, std::mt19937& rng);
void place_trees(Layout& layout, std::mt19937& rng);
void place_poles(Layout& layout, std::mt19937& rng);
void place_car_slots(Layout& layout, std::mt19937& rng);

}  // namespace loopscan::sim
