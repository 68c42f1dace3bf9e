#pragma once
// What `describe` (and `run`, `demo`) write for a described sequence: signatures.txt (rows per
// place stacked), incoming_id_file.txt, frames.txt (descriptor axes per place, row-major 3x3) and
// config.yaml (the configuration it was described with: its method and mode travel with it).
#include <string>

#include "loopscan/config/configuration.hpp"

namespace loopscan::cli {

void write_signatures(const std::string& dir, const SequenceSignatures& result,
                      const Configuration& c);

// What `describe` computes from these files (default mode: the VO resets it detects), with the
// signatures at signatures.txt's digits: numbers printed from them are the ones `evaluate`
// recomputes from the written files (demo and run's reproduce.sh).
SequenceSignatures describe_as_written(const std::vector<KeyframePose>& poses,
                                       const std::vector<IdPoint>& points, SequenceOptions options,
                                       const Configuration& c);

}  // namespace loopscan::cli
