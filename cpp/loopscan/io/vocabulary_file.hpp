#pragma once
// Vocabulary-tree files: our binary format and the text format of DBoW2 / ORB-SLAM2's
// ORBvoc.txt. Both describe the nodes after the (implicit) root, each with its parent, a leaf
// flag, a 32-byte ORB descriptor and a weight.
//
// ORBvoc.txt: first line `k L scoring weighting`; then one node a line:
// `parent is_leaf d0 ... d31 weight` (descriptor bytes as integers 0..255). Node ids follow the
// line order (first node line = node 1); a parent must come before its children.
//
// Binary: magic "LSVOCAB1", u32 version, i32 k, L, scoring, weighting, u64 node count, then per
// node i32 parent, u8 leaf, 32 descriptor bytes, f32 weight; u32 CRC-32 of everything before.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace loopscan::io {

struct VocabularyRecord {
  int parent = 0;
  bool leaf = false;
  std::array<std::uint8_t, 32> descriptor{};
  float weight = 0;
};

struct VocabularyData {
  int branching = 10, depth = 6, scoring = 0, weighting = 0;
  std::vector<VocabularyRecord> nodes;  // node i + 1 (node 0 is the root)
};

// Errors name the file and line (text) or byte offset (binary) and what was expected.
VocabularyData read_orbvoc_text(const std::string& path);
void write_orbvoc_text(const std::string& path, const VocabularyData& vocabulary);
VocabularyData load_vocabulary(const std::string& path);
void save_vocabulary(const std::string& path, const VocabularyData& vocabulary);

}  // namespace loopscan::io
