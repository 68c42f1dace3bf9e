#include "loopscan/baselines/vocabulary_io.hpp"

#include <fstream>
#include <sstream>

#include <opencv2/core/persistence.hpp>

#include "loopscan/io/errors.hpp"
#include "loopscan/io/file_names.hpp"

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

namespace {

// A node's descriptor string: 32 bytes (DBoW2), or DBoW3's "type cols" header then the bytes.
std::array<std::uint8_t, 32> descriptor_of(const std::string& path, int id,
                                           const std::string& text) {
  std::istringstream in(text);
  std::vector<int> v;
  for (int x; in >> x;) v.push_back(x);
  if (!in.eof())
    throw io::InputError(path, 0, "node " + std::to_string(id) + ": a descriptor of integers");
  std::size_t first = 0;
  if (v.size() == 34 && v[0] == 0 && v[1] == 32) first = 2;  // DBoW3: CV_8U, 32 columns
  if (v.size() - first != 32)
    throw io::InputError(path, 0,
                         "node " + std::to_string(id) + ": a 32-byte ORB descriptor, found " +
                             std::to_string(v.size() - first) + " values");
  std::array<std::uint8_t, 32> d{};
  for (std::size_t k = 0; k < 32; ++k) {
    if (v[first + k] < 0 || v[first + k] > 255)
      throw io::InputError(path, 0, "node " + std::to_string(id) + ": bytes 0..255");
    d[k] = static_cast<std::uint8_t>(v[first + k]);
  }
  return d;
}

}  // namespace

io::VocabularyData read_dbow_yaml(const std::string& path) {
  cv::FileStorage fs;
  try {
    if (!fs.open(path, cv::FileStorage::READ)) throw io::InputError(path, 0, "a readable file");
  } catch (const cv::Exception& e) {
    throw io::InputError(path, 0, std::string("an OpenCV YAML vocabulary (") + e.err + ")");
  }
  const cv::FileNode voc = fs["vocabulary"];
  if (voc.empty() || voc["nodes"].empty() || voc["words"].empty())
    throw io::InputError(path, 0, "a 'vocabulary' map with k, L, nodes and words (DBoW2/DBoW3)");
  io::VocabularyData data;
  data.branching = static_cast<int>(voc["k"]);
  data.depth = static_cast<int>(voc["L"]);
  data.scoring = static_cast<int>(voc["scoringType"]);
  data.weighting = static_cast<int>(voc["weightingType"]);
  if (data.branching < 2 || data.depth < 1) throw io::InputError(path, 0, "k >= 2 and L >= 1");
  const cv::FileNode nodes = voc["nodes"];
  data.nodes.assign(nodes.size(), {});
  std::vector<bool> seen(nodes.size() + 1, false);
  for (const cv::FileNode& n : nodes) {
    const int id = static_cast<int>(n["nodeId"]), parent = static_cast<int>(n["parentId"]);
    if (id < 1 || id > static_cast<int>(nodes.size()) || seen[id])
      throw io::InputError(path, 0,
                           "node ids 1.." + std::to_string(nodes.size()) + " once each, found " +
                               std::to_string(id));
    if (parent < 0 || parent >= id)
      throw io::InputError(path, 0, "node " + std::to_string(id) + ": a parent created before it");
    seen[id] = true;
    io::VocabularyRecord& r = data.nodes[id - 1];
    r.parent = parent;
    r.weight = static_cast<float>(static_cast<double>(n["weight"]));
    r.descriptor = descriptor_of(path, id, static_cast<std::string>(n["descriptor"]));
  }
  for (const cv::FileNode& w : voc["words"]) {
    const int node = static_cast<int>(w["nodeId"]);
    if (node < 1 || node > static_cast<int>(nodes.size()))
      throw io::InputError(path, 0, "word nodes among the node ids, found " + std::to_string(node));
    data.nodes[node - 1].leaf = true;
  }
  return data;
}

Vocabulary read_vocabulary(const std::string& path) {
  if (io::ends_with(path, ".yml") || io::ends_with(path, ".yml.gz") ||
      io::ends_with(path, ".yaml") || io::ends_with(path, ".yaml.gz"))
    return from_records(read_dbow_yaml(path));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw io::InputError(path, 0, "a readable vocabulary file");
  char magic[8] = {};
  in.read(magic, sizeof magic);
  const bool binary = in.gcount() == 8 && std::string(magic, 8) == "LSVOCAB1";
  in.close();
  return from_records(binary ? io::load_vocabulary(path) : io::read_orbvoc_text(path));
}

}  // namespace loopscan::baselines
