#pragma once
// Vocabulary <-> the file records of loopscan::io (binary format and ORBvoc.txt).
#include <string>

#include "loopscan/baselines/vocabulary.hpp"
#include "loopscan/io/vocabulary_file.hpp"

namespace loopscan::baselines {

Vocabulary from_records(const io::VocabularyData& data);
io::VocabularyData to_records(const Vocabulary& vocabulary);

// DBoW2 / DBoW3 vocabularies saved with cv::FileStorage (YAML, `.yml` or `.yml.gz`): k, L,
// scoringType, weightingType, nodes (nodeId, parentId, weight, the 32-byte ORB descriptor as
// integers; DBoW3 prefixes "0 32") and words (wordId, nodeId). Errors name the file and node.
io::VocabularyData read_dbow_yaml(const std::string& path);

// DBoW YAML by its extension; our binary format when the file starts with its magic; else
// ORBvoc.txt text.
Vocabulary read_vocabulary(const std::string& path);

}  // namespace loopscan::baselines
