#pragma once
// Session conditions of the synthetic world: season (foliage, snow), illumination and the seed
// that redraws the parked cars. One world is rendered under several conditions.
#include <string>

namespace loopscan::sim {

enum class Season { Spring, Summer, Fall, Winter };

// "spring" | "summer" | "fall" | "winter"; anything else throws std::invalid_argument.
Season parse_season(const std::string& name);
std::string season_name(Season season);

struct Conditions {
  Season season = Season::Summer;
  double illumination_gain = 1.0;  // gray = 255 * clamp(gain * albedo, 0, 1)^gamma
  double gamma = 1.0;
  unsigned session_seed = 1;  // parked cars are redrawn from (world seed, session seed)
  // Seed of a session's random draws (VO noise, sensor noise) from the world seed.
  unsigned noise_seed(unsigned world_seed) const { return world_seed * 7919u + session_seed; }

  // Typical light of the season (winter: low sun, darker); session_seed stays 1.
  static Conditions for_season(Season s);
};

// Season effects, tuned here so that the world's shading and the tests agree.
// Probability that a foliage voxel of a crown holds leaves (or bare branches in winter).
double foliage_density(Season season);
// Base albedo of the foliage (summer dark green, spring lighter, fall orange/brown, winter bark).
double foliage_albedo(Season season);
// Snow covers ground, sidewalks and roofs (the road is cleared).
bool has_snow(Season season);

}  // namespace loopscan::sim
