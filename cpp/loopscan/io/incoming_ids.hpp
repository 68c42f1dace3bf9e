#pragma once
// The incoming-id file: the keyframe id of each signature, one integer a line.
#include <string>
#include <vector>

namespace loopscan::io {

// One non-negative integer a line; blank lines only at the end. .gz is supported.
std::vector<int> read_incoming_ids(const std::string& path);

// Writes one id a line, atomically (gzip-compressed when `path` ends in ".gz").
void write_incoming_ids(const std::string& path, const std::vector<int>& ids);

}  // namespace loopscan::io
