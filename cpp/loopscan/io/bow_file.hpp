#pragma once
// Bag-of-Words vectors of a described sequence (`describe --method bow`): bow.txt, one place a
// line, `word weight word weight ...` (word ids increasing, weights > 0; an empty line is a
// place without words).
#include <string>
#include <utility>
#include <vector>

namespace loopscan::io {

using SparseVector = std::vector<std::pair<int, float>>;

void write_bow_vectors(const std::string& path, const std::vector<SparseVector>& vectors);
// Errors name the file and line: odd token count, non-numbers, word ids not increasing or
// negative, weights not finite and positive.
std::vector<SparseVector> read_bow_vectors(const std::string& path);

}  // namespace loopscan::io
