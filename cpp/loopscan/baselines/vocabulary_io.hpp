#pragma once
// Vocabulary <-> the file records of loopscan::io (binary format and ORBvoc.txt).
#include <string>

#include "loopscan/baselines/vocabulary.hpp"
#include "loopscan/io/vocabulary_file.hpp"

namespace loopscan::baselines {

Vocabulary from_records(const io::VocabularyData& data);
io::VocabularyData to_records(const Vocabulary& vocabulary);

// Our binary format when the file starts with its magic, else ORBvoc.txt text.
Vocabulary read_vocabulary(const std::string& path);

}  // namespace loopscan::baselines
