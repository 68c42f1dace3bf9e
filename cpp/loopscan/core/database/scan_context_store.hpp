#pragma once
// The index keys of the Scan Context store (scan_context_store.cpp): the spectral key (uint16,
// per ring of both halves the DC term and the magnitudes of the lowest harmonics, ring key
// first) and the coarse key KeyScan searches, taken from it.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace loopscan {

// Harmonics per ring in the spectral key, after the DC term.
constexpr int kSpectralKeyFrequencies = 2;

// Squared distance of two spectral keys, exact.
std::uint64_t spectral_key_distance(const std::uint16_t* a, const std::uint16_t* b, std::size_t n);

// The coarse key: the DC terms of every ring of both halves (Scan Context's ring key and its
// intensity counterpart) in steps of 8 / 8192 (13 bits, KeyScan's range); more rings than
// KeyScan::kMaxDims / 2 are averaged in consecutive groups. Summing rings in pairs (a 10-D key,
// for a KD-tree) lost the exact best place among near-identical ones; the intensity terms
// separate places across seasons (docs/database.md).
int coarse_key_dims(int rings);
std::vector<std::uint16_t> coarse_key(const std::vector<std::uint16_t>& spectral_key, int rings);

}  // namespace loopscan
