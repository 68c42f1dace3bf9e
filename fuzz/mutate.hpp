#pragma once
// Seeded mutations of one input file: byte-level (flips, overwrites with boundary values,
// truncation, junk) for every format, plus token- and line-level ones for text (numbers
// replaced by NaN, infinities, 1e308, huge integers, junk; lines duplicated, dropped,
// swapped, cut), and checksum repair for the binary formats that carry one.
#include <random>
#include <string>

#include "fuzz_target.hpp"

namespace loopscan::fuzz {

// 1 to 4 mutations of `bytes`, chosen by `rng`; deterministic for a given rng state.
std::string mutate(const std::string& bytes, const Target& target, std::mt19937_64& rng);

// CRC repairs (exposed for the driver's tests of the targets themselves).
void fix_trailing_crc(std::string& bytes);
void fix_png_crcs(std::string& bytes);

}  // namespace loopscan::fuzz
