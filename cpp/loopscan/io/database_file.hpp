#pragma once
// The place database on disk: a versioned little-endian binary file.
//   "LOOPSCDB" | u32 version = 4 | header | places | clouds | u32 CRC-32 of everything before it
//   header: u32 method, u32 fusion, f64 structure weight, i32 rings, i32 sectors,
//           i32 columns, u32 storage (version 3: 0 full, 1 compact Scan Context spectra),
//           u8 mode, u8 descriptor frame (version 4: how the places were described; 255
//           unknown), u32 payload floats, u64 place count
//   place:  i32 session, i32 keyframe, u8 has pose, f32 frame[9] (row-major),
//           f64 pose[12] (3x4 row-major, only if has pose), f32 payload[payload floats]
//   clouds (version 2): u8 present; if 1, per place: u32 points n, u32 structure points
//           (<= n), i16 xyz[3n] in centimetres (camera frame, |v| < 327.67 m)
// Version 1 (no cloud section), 2 (no storage field: full) and 3 (mode and frame unknown) files
// still load.
// Saving is atomic (temp file + rename). Loading checks magic, version, parameters, the exact
// file size for the stated count (before allocating anything), every field's range and the
// checksum, and throws io::InputError naming the file and the byte offset otherwise. A save
// of a loaded database reproduces the file byte for byte.
#include <string>
#include <vector>

#include "loopscan/core/database/database.hpp"
#include "loopscan/core/place_cloud.hpp"

namespace loopscan::io {

inline constexpr unsigned kDatabaseFileVersion = 6;

// `clouds` (optional): one per place, saved with it (points rounded to 1 cm; farther than
// 327 m from the keyframe: std::invalid_argument).
void save_database(const Database& db, const std::string& path,
                   const std::vector<PlaceCloud>* clouds = nullptr);

// `expected` (optional): the parameters the caller needs; a file built with others is
// rejected (method, fusion, weight, rings, sectors, columns). `clouds` (optional) receives the
// places' clouds, empty when the file has none.
Database load_database(const std::string& path, const DatabaseConfig* expected = nullptr,
                       std::vector<PlaceCloud>* clouds = nullptr);

}  // namespace loopscan::io
