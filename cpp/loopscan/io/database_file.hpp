#pragma once
// The place database on disk: a versioned little-endian binary file.
//   "LOOPSCDB" | u32 version = 1 | header | places | u32 CRC-32 of everything before it
//   header: u32 method, u32 fusion, f64 structure weight, i32 rings, i32 sectors,
//           i32 columns, u32 payload floats, u64 place count
//   place:  i32 session, i32 keyframe, u8 has pose, f32 frame[9] (row-major),
//           f64 pose[12] (3x4 row-major, only if has pose), f32 payload[payload floats]
// Saving is atomic (temp file + rename). Loading checks magic, version, parameters, the exact
// file size for the stated count (before allocating anything), every field's range and the
// checksum, and throws io::InputError naming the file and the byte offset otherwise. A save
// of a loaded database reproduces the file byte for byte.
#include <string>

#include "loopscan/core/database/database.hpp"

namespace loopscan::io {

inline constexpr unsigned kDatabaseFileVersion = 1;

void save_database(const Database& db, const std::string& path);

// `expected` (optional): the parameters the caller needs; a file built with others is
// rejected (method, fusion, weight, rings, sectors, columns).
Database load_database(const std::string& path, const DatabaseConfig* expected = nullptr);

}  // namespace loopscan::io
