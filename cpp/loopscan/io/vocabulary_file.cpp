#include "loopscan/io/vocabulary_file.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "loopscan/io/atomic_file.hpp"
#include "loopscan/io/binary_stream.hpp"
#include "loopscan/io/errors.hpp"
#include "loopscan/io/line_reader.hpp"
#include "loopscan/io/parse_numbers.hpp"

namespace loopscan::io {
namespace {

constexpr char kMagic[8] = {'L', 'S', 'V', 'O', 'C', 'A', 'B', '1'};
constexpr std::uint32_t kVersion = 1;
constexpr std::size_t kHeaderBytes = 8 + 4 + 4 * 4 + 8;
constexpr std::size_t kNodeBytes = 4 + 1 + 32 + 4;

// Header ranges shared by both formats; returns an empty string when valid.
std::string header_problem(const VocabularyData& v) {
  if (v.branching < 2 || v.branching > 1000) return "branching k in 2..1000";
  if (v.depth < 1 || v.depth > 32) return "depth L in 1..32";
  if (v.scoring < 0 || v.scoring > 5) return "scoring code in 0..5";
  if (v.weighting < 0 || v.weighting > 3) return "weighting code in 0..3";
  return "";
}

// Structural checks of a node about to be appended as node `id` (1-based).
std::string node_problem(const VocabularyData& v, const VocabularyRecord& n, std::size_t id) {
  if (n.parent < 0 || static_cast<std::size_t>(n.parent) >= id)
    return "a parent id in 0.." + std::to_string(id - 1) + " (an earlier node), got " +
           std::to_string(n.parent);
  if (n.parent > 0 && v.nodes[static_cast<std::size_t>(n.parent) - 1].leaf)
    return "a parent that is not a leaf (node " + std::to_string(n.parent) + " is a leaf)";
  if (!std::isfinite(n.weight) || n.weight < 0) return "a finite non-negative weight";
  return "";
}

}  // namespace

VocabularyData read_orbvoc_text(const std::string& path) {
  LineReader reader(path);
  std::string_view line;
  VocabularyData v;
  const char* header = "a header line `k L scoring weighting` (4 integers)";
  if (!reader.next(line)) throw InputError(path, 1, header);
  {
    Tokenizer t(line);
    std::string_view tok;
    int* fields[4] = {&v.branching, &v.depth, &v.scoring, &v.weighting};
    for (int* f : fields)
      if (!t.next(tok) || !parse_number(tok, *f)) throw InputError(path, 1, header);
    if (!t.at_end()) throw InputError(path, 1, header);
    const std::string problem = header_problem(v);
    if (!problem.empty()) throw InputError(path, 1, problem);
  }
  const char* node_line = "a node line `parent is_leaf d0 ... d31 weight` (35 numbers)";
  while (reader.next(line)) {
    if (is_blank(line)) continue;
    Tokenizer t(line);
    std::string_view tok;
    VocabularyRecord n;
    int leaf = 0;
    if (!t.next(tok) || !parse_number(tok, n.parent))
      throw InputError(path, reader.line_number(), node_line);
    if (!t.next(tok) || !parse_number(tok, leaf) || (leaf != 0 && leaf != 1))
      throw InputError(path, reader.line_number(), "is_leaf 0 or 1 after the parent id");
    for (std::uint8_t& byte : n.descriptor) {
      int b = 0;
      if (!t.next(tok) || !parse_number(tok, b) || b < 0 || b > 255)
        throw InputError(path, reader.line_number(), "32 descriptor bytes (integers 0..255)");
      byte = static_cast<std::uint8_t>(b);
    }
    if (!t.next(tok) || !parse_number(tok, n.weight) || !t.at_end())
      throw InputError(path, reader.line_number(), node_line);
    n.leaf = leaf == 1;
    const std::string problem = node_problem(v, n, v.nodes.size() + 1);
    if (!problem.empty()) throw InputError(path, reader.line_number(), problem);
    v.nodes.push_back(n);
    check_record_count(reader, v.nodes.size(), "vocabulary nodes");
  }
  if (v.nodes.empty()) throw InputError(path, reader.line_number() + 1, node_line);
  return v;
}

void write_orbvoc_text(const std::string& path, const VocabularyData& v) {
  std::ostringstream s;
  s << v.branching << ' ' << v.depth << ' ' << v.scoring << ' ' << v.weighting << '\n';
  s.precision(9);
  for (const VocabularyRecord& n : v.nodes) {
    s << n.parent << ' ' << (n.leaf ? 1 : 0);
    for (std::uint8_t b : n.descriptor) s << ' ' << static_cast<int>(b);
    s << ' ' << n.weight << '\n';
  }
  write_file_atomic(path, s.str());
}

void save_vocabulary(const std::string& path, const VocabularyData& v) {
  AtomicWriter file(path);
  Writer w(file.stream());
  w.bytes(kMagic, sizeof kMagic);
  w.put<std::uint32_t>(kVersion);
  for (int x : {v.branching, v.depth, v.scoring, v.weighting}) w.put<std::int32_t>(x);
  w.put<std::uint64_t>(v.nodes.size());
  for (const VocabularyRecord& n : v.nodes) {
    w.put<std::int32_t>(n.parent);
    w.put<std::uint8_t>(n.leaf ? 1 : 0);
    w.bytes(n.descriptor.data(), 32);
    w.put<float>(n.weight);
  }
  const std::uint32_t crc = w.crc();
  file.stream().write(reinterpret_cast<const char*>(&crc), sizeof crc);
  file.commit();
}

VocabularyData load_vocabulary(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "a readable vocabulary file");
  std::error_code ec;
  const std::uintmax_t file_size = std::filesystem::file_size(path, ec);
  Reader r(in, path);
  char magic[8];
  r.bytes(magic, sizeof magic, "the magic \"LSVOCAB1\"");
  if (std::string(magic, 8) != std::string(kMagic, 8))
    r.fail("not a loopscan vocabulary (for ORBvoc.txt use the text format)");
  const auto version = r.get<std::uint32_t>("the version");
  if (version != kVersion)
    r.fail("version " + std::to_string(version) + ", expected " + std::to_string(kVersion));
  VocabularyData v;
  v.branching = r.get<std::int32_t>("k");
  v.depth = r.get<std::int32_t>("L");
  v.scoring = r.get<std::int32_t>("the scoring code");
  v.weighting = r.get<std::int32_t>("the weighting code");
  const std::string problem = header_problem(v);
  if (!problem.empty()) r.fail("expected " + problem);
  const auto count = r.get<std::uint64_t>("the node count");
  if (ec || file_size < kHeaderBytes + 4 || count > (file_size - kHeaderBytes - 4) / kNodeBytes)
    r.fail("the file is too short for " + std::to_string(count) + " nodes (truncated?)");
  v.nodes.reserve(count);
  for (std::uint64_t i = 0; i < count; ++i) {
    VocabularyRecord n;
    n.parent = r.get<std::int32_t>("a parent id");
    const auto leaf = r.get<std::uint8_t>("a leaf flag");
    if (leaf > 1) r.fail("leaf flag " + std::to_string(leaf) + ", expected 0 or 1");
    n.leaf = leaf == 1;
    r.bytes(n.descriptor.data(), 32, "a descriptor");
    n.weight = r.get<float>("a weight");
    const std::string node = node_problem(v, n, v.nodes.size() + 1);
    if (!node.empty()) r.fail("node " + std::to_string(i + 1) + ": expected " + node);
    v.nodes.push_back(n);
  }
  const std::uint32_t crc = r.crc();
  std::uint32_t stored = 0;
  if (!in.read(reinterpret_cast<char*>(&stored), sizeof stored))
    r.fail("unexpected end of file, expected the checksum");
  if (stored != crc) r.fail("checksum mismatch: the file is corrupted");
  if (in.peek() != std::char_traits<char>::eof()) r.fail("unexpected data after the checksum");
  return v;
}

}  // namespace loopscan::io
