#include "loopscan/sim/conditions.hpp"

#include <stdexcept>

namespace loopscan::sim {

Season parse_season(const std::string& name) {
  if (name == "spring") return Season::Spring;
  if (name == "summer") return Season::Summer;
  if (name == "fall") return Season::Fall;
  if (name == "winter") return Season::Winter;
  throw std::invalid_argument("unknown season '" + name + "' (spring|summer|fall|winter)");
}

std::string season_name(Season season) {
  switch (season) {
    case Season::Spring:
      return "spring";
    case Season::Summer:
      return "summer";
    case Season::Fall:
      return "fall";
    case Season::Winter:
      return "winter";
  }
  throw std::invalid_argument("invalid Season value");
}

Conditions Conditions::for_season(Season s) {
  Conditions c;
  c.season = s;
  switch (s) {
    case Season::Spring:
      c.illumination_gain = 0.95;
      c.gamma = 1.0;
      break;
    case Season::Summer:
      c.illumination_gain = 1.0;
      c.gamma = 1.0;
      break;
    case Season::Fall:
      c.illumination_gain = 0.9;
      c.gamma = 1.05;
      break;
    case Season::Winter:
      // Low sun: darker overall, gamma > 1 pushes the mid-tones down further.
      c.illumination_gain = 0.8;
      c.gamma = 1.1;
      break;
  }
  return c;
}

double foliage_density(Season season) {
  // Nested thresholds on the same voxel hash: winter branches are a subset of summer leaves.
  switch (season) {
    case Season::Spring:
      return 0.4;
    case Season::Summer:
      return 0.55;
    case Season::Fall:
      return 0.28;
    case Season::Winter:
      return 0.012;
  }
  return 0.0;
}

double foliage_albedo(Season season) {
  switch (season) {
    case Season::Spring:
      return 0.34;
    case Season::Summer:
      return 0.2;
    case Season::Fall:
      return 0.45;
    case Season::Winter:
      return 0.27;
  }
  return 0.2;
}

bool has_snow(Season season) { return season == Season::Winter; }

}  // namespace loopscan::sim
