#pragma once
// What `describe` (and `run`) write for a described sequence: signatures.txt (rows per place
// stacked), incoming_id_file.txt and frames.txt (descriptor axes per place, row-major 3x3).
#include <string>

#include "loopscan/core/pipeline/describe_sequence.hpp"

namespace loopscan::cli {

void write_signatures(const std::string& dir, const SequenceSignatures& result, Method method);

}  // namespace loopscan::cli
