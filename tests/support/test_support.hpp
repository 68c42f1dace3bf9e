#pragma once
// Helpers shared by the test files: the ../shared location, random clouds, fixture loading.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>

#include "loopscan/core/types.hpp"

namespace loopscan::test {

inline std::string shared_dir() {
  if (const char* env = std::getenv("LOOPSCAN_SHARED")) return env;
  return LOOPSCAN_SHARED_DIR;
}

inline std::string fixture_dir() { return shared_dir() + "/fixtures/k06-summer"; }

// A path in the temporary directory that is this test process's own (`name` and the pid), so
// that two suites running at once never share one.
inline std::filesystem::path temp_path(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("loopscan_" + name + "_" + std::to_string(::getpid()));
}

// LOOPSCAN_REQUIRE_SHARED=1 (CI sets it): a test whose shared data is absent fails instead of
// skipping, so that a missing reference file cannot leave CI green.
inline bool shared_required() {
  const char* env = std::getenv("LOOPSCAN_REQUIRE_SHARED");
  return env && *env && std::string(env) != "0";
}

// Ends the test when shared data it needs is absent (`present` false), saying what it needs
// (`what`, streamed): skipped, or failed where shared data is required.
#define LOOPSCAN_SKIP_WITHOUT_SHARED(present, what)                    \
  if (present) {                                                       \
  } else if (::loopscan::test::shared_required())                      \
    FAIL() << "needs " << what << " (LOOPSCAN_REQUIRE_SHARED is set)"; \
  else                                                                 \
    GTEST_SKIP() << "needs " << what << " (set LOOPSCAN_SHARED to the shared/ folder)"

#define LOOPSCAN_REQUIRE_FIXTURE()                                                          \
  LOOPSCAN_SKIP_WITHOUT_SHARED(                                                             \
      std::filesystem::exists(::loopscan::test::fixture_dir() + "/poses_history_file.txt"), \
      "the k06 fixture at " << ::loopscan::test::fixture_dir())

// A street-like cloud in the camera frame (x right, y down, z forward): two facades, a ground
// strip and some clutter, with gray values. Deterministic in `seed`.
inline Cloud street_cloud(unsigned seed, int n = 3000) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Cloud c;
  for (int i = 0; i < n; ++i) {
    const int kind = i % 4;
    Eigen::Vector3d p;
    if (kind == 0) p = {-8 + 0.3 * u(rng), -6 * std::abs(u(rng)) + 1.5, 40 * u(rng)};
    if (kind == 1) p = {9 + 0.3 * u(rng), -10 * std::abs(u(rng)) + 1.5, 40 * u(rng)};
    if (kind == 2) p = {8 * u(rng), 1.6 + 0.05 * u(rng), 40 * u(rng)};
    if (kind == 3) p = {20 * u(rng), -3 * std::abs(u(rng)), 30 * u(rng) + 5};
    const float gray = static_cast<float>(127.5 + 120 * std::sin(0.7 * p.z() + kind));
    c.push_back({p, gray});
  }
  return c;
}

inline Cloud transformed(const Cloud& c, const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  Cloud out = c;
  for (PointI& q : out) q.p = R * q.p + t;
  return out;
}

}  // namespace loopscan::test
