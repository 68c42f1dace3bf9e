#pragma once
// Preconditions of the place database, checked where values enter it (construction, add,
// load, query): each check throws std::invalid_argument naming the value, so a NaN or a
// nonsensical option never turns into NaN distances or unbounded work.
#include <cstddef>
#include <optional>

#include "loopscan/core/database/database.hpp"

namespace loopscan {

// Structure weight finite in [0, 1000]; Scan Context rings and sectors as validate() allows.
void validate(const DatabaseConfig& config);
// k in [0, 10^6], candidates in [1, 10^6], pool factor in [1, 1000], stats sample in
// [2, 10^6], exclude_recent >= 0, uniqueness ratio in [0, 1], max_distance not NaN,
// distinct_gap >= 0, threads in [1, 1024].
void validate(const QueryOptions& options, int k);

// Throws std::invalid_argument when the places of `map` were described otherwise than `own`
// describes (the method; the mode and the descriptor frame where the map records them), naming
// both. `who` starts the message.
void require_same_description(const DatabaseConfig& map, const DatabaseConfig& own,
                              const char* who);

// Every value finite and within +-1e30 (signatures, payloads); every frame and pose entry
// finite. `who` starts the message.
void require_finite_values(const float* values, std::size_t n, const char* who);
void require_finite_values(const Signature& signature, const char* who);
void require_finite_frame_and_pose(const Eigen::Matrix3f& frame,
                                   const std::optional<Pose3x4>& T_cam_world, const char* who);

}  // namespace loopscan
