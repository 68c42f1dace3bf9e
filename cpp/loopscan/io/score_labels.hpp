#pragma once
// Pairwise `score label` files (other detectors' published results): one pair a line.
#include <string>
#include <vector>

#include "loopscan/eval/pairwise.hpp"

namespace loopscan::io {

// Each line: a finite score, then the label 0 or 1 (exactly; "1.0" is accepted, 0.5 or 2 are
// not). Gzip is read transparently. Errors name the file, the line and this format.
std::vector<eval::ScoreLabel> read_score_labels(const std::string& path);

}  // namespace loopscan::io
