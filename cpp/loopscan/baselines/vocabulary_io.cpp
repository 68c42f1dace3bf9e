#include "loopscan/baselines/vocabulary_io.hpp"

#include <fstream>

#include "loopscan/io/errors.hpp"

namespace loopscan::baselines {

Vocabulary from_records(const io::VocabularyData& data) {
  std::vector<VocabularyNode> nodes(1);
  nodes.reserve(data.nodes.size() + 1);
  for (const io::VocabularyRecord& r : data.nodes) {
    VocabularyNode n;
    n.parent = r.parent;
    n.descriptor = r.descriptor;
    n.weight = r.weight;
    n.word = r.leaf ? 0 : -1;
    nodes.push_back(n);
  }
  return Vocabulary(data.branching, data.depth, data.scoring, data.weighting, std::move(nodes));
}

io::VocabularyData to_records(const Vocabulary& v) {
  io::VocabularyData data;
  data.branching = v.branching;
  data.depth = v.depth;
  data.scoring = v.scoring;
  data.weighting = v.weighting;
  for (std::size_t i = 1; i < v.nodes().size(); ++i) {
    const VocabularyNode& n = v.nodes()[i];
    data.nodes.push_back({n.parent, n.word >= 0, n.descriptor, n.weight});
  }
  return data;
}

Vocabulary read_vocabulary(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw io::InputError(path, 0, "a readable vocabulary file");
  char magic[8] = {};
  in.read(magic, sizeof magic);
  const bool binary = in.gcount() == 8 && std::string(magic, 8) == "LSVOCAB1";
  in.close();
  return from_records(binary ? io::load_vocabulary(path) : io::read_orbvoc_text(path));
}

}  // namespace loopscan::baselines
