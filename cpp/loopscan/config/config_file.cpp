#include "loopscan/config/config_file.hpp"

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "loopscan/config/keys.hpp"
#include "loopscan/io/atomic_file.hpp"
#include "loopscan/io/errors.hpp"

namespace loopscan {
namespace {

using config_keys::Range;

constexpr std::uintmax_t kMaxConfigBytes = 1 << 20;  // every key with comments is ~25 KB

// Names of the enumerated keys' values, both ways.
template <typename E>
struct EnumNames;
template <>
struct EnumNames<Mode> {
  static constexpr const char* kChoices = "default or reference";
  static Mode parse(const std::string& s) { return parse_mode(s); }
  static std::string name(Mode m) { return mode_name(m); }
};
template <>
struct EnumNames<DescriptorFrame> {
  static constexpr const char* kChoices = "pca, camera, gravity-pca or centroid";
  static DescriptorFrame parse(const std::string& s) { return parse_descriptor_frame(s); }
  static std::string name(DescriptorFrame f) { return descriptor_frame_name(f); }
};
template <>
struct EnumNames<BirdsEyeCell> {
  static constexpr const char* kChoices = "density or height";
  static BirdsEyeCell parse(const std::string& s) { return parse_birds_eye_cell(s); }
  static std::string name(BirdsEyeCell c) { return birds_eye_cell_name(c); }
};
template <>
struct EnumNames<Fusion> {
  static constexpr const char* kChoices = "adaptive, fused, structure or intensity";
  static Fusion parse(const std::string& s) { return parse_fusion(s); }
  static std::string name(Fusion f) { return fusion_name(f); }
};
template <>
struct EnumNames<PlaceStorage> {
  static constexpr const char* kChoices = "full or compact";
  static PlaceStorage parse(const std::string& s) { return parse_storage(s); }
  static std::string name(PlaceStorage s) { return storage_name(s); }
};
template <>
struct EnumNames<Retrieval> {
  static constexpr const char* kChoices = "indexed or exact";
  static Retrieval parse(const std::string& s) { return parse_retrieval(s); }
  static std::string name(Retrieval r) { return retrieval_name(r); }
};

// ---------------------------------------------------------------- writing

// The shortest text that reads back as the same double; whole numbers without an exponent.
std::string number_text(double v) {
  if (std::isinf(v)) return v > 0 ? ".inf" : "-.inf";
  char buf[40];
  if (v == std::floor(v) && std::abs(v) < 1e15) {
    std::snprintf(buf, sizeof buf, "%.0f", v);
    return buf;
  }
  for (int precision = 1; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*g", precision, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

// The same for a float: the shortest text that reads back as the same float.
std::string float_text(float v) {
  if (!std::isfinite(v) || v == std::floor(v)) return number_text(v);
  char buf[40];
  for (int precision = 1; precision <= 9; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*g", precision, static_cast<double>(v));
    if (std::strtof(buf, nullptr) == v) break;
  }
  return buf;
}

class Writer {
 public:
  Writer(std::ostringstream& out, bool with_method) : out_(out), with_method_(with_method) {}

  template <typename Body>
  void section(const char* name, const char* doc, Body body) {
    if (depth_ == 0) out_ << '\n';
    line(std::string(name) + ":", doc);
    ++depth_;
    body();
    --depth_;
  }
  void key(const char* name, double& v, const Range&, const char* doc) {
    line(std::string(name) + ": " + number_text(v), doc);
  }
  void key(const char* name, float& v, const Range&, const char* doc) {
    line(std::string(name) + ": " + float_text(v), doc);
  }
  void key(const char* name, int& v, const Range&, const char* doc) {
    line(std::string(name) + ": " + std::to_string(v), doc);
  }
  void key(const char* name, unsigned& v, const Range&, const char* doc) {
    line(std::string(name) + ": " + std::to_string(v), doc);
  }
  void key(const char* name, std::optional<double>& v, const Range&, const char* doc) {
    line(std::string(name) + ": " + (v ? number_text(*v) : "null"), doc);
  }
  template <typename T>
  void key(const char* name, std::vector<T>& v, const Range&, const char* doc) {
    std::string text = std::string(name) + ": [";
    for (std::size_t i = 0; i < v.size(); ++i)
      text += (i ? ", " : "") + number_text(static_cast<double>(v[i]));
    line(text + "]", doc);
  }
  void key(const char* name, bool& v, const char* doc) {
    line(std::string(name) + ": " + (v ? "true" : "false"), doc);
  }
  template <typename E>
  void key(const char* name, E& v, const char* doc) {
    line(std::string(name) + ": " + EnumNames<E>::name(v), doc);
  }
  void method_key(const char* name, Configuration& c, const char* doc) {
    if (with_method_) line(std::string(name) + ": " + method_name(c), doc);
  }

 private:
  // "key: value  # doc", the description on the lines above when that would pass 100 columns.
  void line(const std::string& text, const char* doc) {
    const std::string indent(2 * depth_, ' ');
    const std::string d = doc ? doc : "";
    if (d.empty()) {
      out_ << indent << text << '\n';
    } else if (indent.size() + text.size() + 4 + d.size() <= 100) {
      out_ << indent << text << "  # " << d << '\n';
    } else {
      std::istringstream words(d);
      std::string word, comment = indent + "#";
      while (words >> word) {
        if (comment.size() + 1 + word.size() > 100) {
          out_ << comment << '\n';
          comment = indent + "#";
        }
        comment += " " + word;
      }
      out_ << comment << '\n' << indent << text << '\n';
    }
  }

  std::ostringstream& out_;
  bool with_method_;
  int depth_ = 0;
};

// ---------------------------------------------------------------- reading

std::size_t line_of(const YAML::Node& n) { return static_cast<std::size_t>(n.Mark().line) + 1; }

// The entry `name` of a YAML map (key and value), or nullopt.
std::optional<std::pair<YAML::Node, YAML::Node>> find_key(const YAML::Node& map,
                                                          const std::string& name) {
  if (!map.IsMap()) return std::nullopt;
  for (const auto& kv : map) {
    if (kv.first.IsScalar() && kv.first.Scalar() == name)
      return std::make_pair(kv.first, kv.second);
  }
  return std::nullopt;
}

class Reader {
 public:
  Reader(std::string path, const YAML::Node& root) : path_(std::move(path)) {
    if (!root.IsNull() && !root.IsMap())
      throw io::InputError(path_, line_of(root), "a YAML map of configuration keys at the top");
    levels_.push_back({"", root.IsMap() ? root : YAML::Node(YAML::NodeType::Map), {}});
    check_duplicates(levels_.back().node, "");
  }

  template <typename Body>
  void section(const char* name, const char*, Body body) {
    levels_.back().known.push_back(name);
    const std::optional<YAML::Node> child = find(name);
    if (!child || child->IsNull()) return;  // absent or empty: every key keeps its default
    if (!child->IsMap()) fail(*child, dotted(name), "a map of keys", text(*child));
    check_duplicates(*child, dotted(name));
    levels_.push_back({dotted(name), *child, {}});
    body();
    finish_level();
    levels_.pop_back();
  }

  void key(const char* name, double& v, const Range& r, const char* /*doc*/) {
    if (const auto n = scalar(name)) v = number(*n, dotted(name), r);
  }
  void key(const char* name, float& v, const Range& r, const char* doc) {
    double d = v;
    key(name, d, r, doc);
    v = static_cast<float>(d);
  }
  void key(const char* name, int& v, const Range& r, const char*) {
    if (const auto n = scalar(name)) v = static_cast<int>(whole(*n, dotted(name), r));
  }
  void key(const char* name, unsigned& v, const Range& r, const char*) {
    if (const auto n = scalar(name)) v = static_cast<unsigned>(whole(*n, dotted(name), r));
  }
  void key(const char* name, std::optional<double>& v, const Range& r, const char*) {
    levels_.back().known.push_back(name);
    const std::optional<YAML::Node> n = find(name);
    if (!n) return;
    if (n->IsNull()) {
      v.reset();
      return;
    }
    if (!n->IsScalar()) fail(*n, dotted(name), "a number or null", text(*n));
    v = number(*n, dotted(name), r);
  }
  template <typename T>
  void key(const char* name, std::vector<T>& v, const Range& r, const char*) {
    levels_.back().known.push_back(name);
    const std::optional<YAML::Node> n = find(name);
    if (!n) return;
    const std::string key = dotted(name);
    const std::string what = std::string("a list of at most ") + std::to_string(r.max_items) +
                             (std::is_integral<T>::value ? " whole numbers" : " numbers") + " in " +
                             range_text(r);
    if (!n->IsSequence()) fail(*n, key, what, text(*n));
    if (n->size() > r.max_items) fail(*n, key, what, std::to_string(n->size()) + " items");
    std::vector<T> values;
    for (const YAML::Node& item : *n) {
      if (!item.IsScalar()) fail(item, key, what, text(item));
      if constexpr (std::is_integral<T>::value) {
        values.push_back(static_cast<T>(whole(item, key, r)));
      } else {
        values.push_back(static_cast<T>(number(item, key, r)));
      }
    }
    v = std::move(values);
  }
  void key(const char* name, bool& v, const char*) {
    const auto n = scalar(name);
    if (!n) return;
    const std::string s = n->Scalar();
    if (s == "true" || s == "True" || s == "TRUE") {
      v = true;
    } else if (s == "false" || s == "False" || s == "FALSE") {
      v = false;
    } else {
      fail(*n, dotted(name), "true or false", s);
    }
  }
  template <typename E>
  void key(const char* name, E& v, const char*) {
    const auto n = scalar(name);
    if (!n) return;
    try {
      v = EnumNames<E>::parse(n->Scalar());
    } catch (const std::invalid_argument&) {
      fail(*n, dotted(name), EnumNames<E>::kChoices, n->Scalar());
    }
  }

  void method_key(const char* name, Configuration& c, const char*) {
    const auto n = scalar(name);
    if (!n) return;
    try {
      parse_method_name(n->Scalar(), c.method, c.image_baseline);
    } catch (const std::invalid_argument&) {
      fail(*n, dotted(name), method_choices(), n->Scalar());
    }
  }

  // After the whole visit: keys of the top level that no visit asked for.
  void finish() { finish_level(); }

 private:
  struct Level {
    std::string prefix;  // "closure.verification"
    YAML::Node node;
    std::vector<std::string> known;  // the names the visit asked for
  };

  std::string dotted(const char* name) const {
    return levels_.back().prefix.empty() ? name : levels_.back().prefix + "." + name;
  }

  std::optional<YAML::Node> find(const char* name) {
    const auto entry = find_key(levels_.back().node, name);
    if (!entry) return std::nullopt;
    key_line_ = line_of(entry->first);
    return entry->second;
  }

  // The key's value, which must be a scalar, or nullopt when the file leaves it out.
  std::optional<YAML::Node> scalar(const char* name) {
    levels_.back().known.push_back(name);
    const std::optional<YAML::Node> n = find(name);
    if (n && !n->IsScalar()) fail(*n, dotted(name), "a single value", text(*n));
    return n;
  }

  void check_duplicates(const YAML::Node& map, const std::string& prefix) const {
    std::set<std::string> names;
    for (const auto& kv : map) {
      const std::string name = kv.first.IsScalar() ? kv.first.Scalar() : "";
      if (!names.insert(name).second) {
        throw io::InputError(path_, line_of(kv.first),
                             "each key once, got '" + name + "' again" +
                                 (prefix.empty() ? "" : " in '" + prefix + "'"));
      }
    }
  }

  void finish_level() {
    const Level& level = levels_.back();
    for (const auto& kv : level.node) {
      const std::string name = kv.first.IsScalar() ? kv.first.Scalar() : "?";
      bool known = false;
      for (const std::string& k : level.known) known = known || k == name;
      if (known) continue;
      std::string expected =
          "a key of " +
          (level.prefix.empty() ? std::string("the top level") : "'" + level.prefix + "'") + " (";
      for (std::size_t i = 0; i < level.known.size(); ++i)
        expected += (i ? ", " : "") + level.known[i];
      expected += "), got '" + name + "'";
      const std::string guess = io::closest_name(name, level.known);
      if (!guess.empty()) expected += " (did you mean '" + guess + "'?)";
      throw io::InputError(path_, line_of(kv.first), expected);
    }
  }

  static std::string text(const YAML::Node& n) {
    if (n.IsScalar()) return n.Scalar();
    if (n.IsNull()) return "nothing";
    if (n.IsSequence()) return "a list";
    if (n.IsMap()) return "a map";
    return "?";
  }

  static std::string range_text(const Range& r) {
    return std::string(r.lo_open ? "(" : "[") + number_text(r.lo) + ", " + number_text(r.hi) + "]";
  }

  // An empty value has no line of its own: its key's.
  [[noreturn]] void fail(const YAML::Node& n, const std::string& key, const std::string& what,
                         const std::string& got) const {
    throw io::InputError(path_, n.IsNull() ? key_line_ : line_of(n),
                         what + " for " + key + ", got '" + got + "'");
  }

  bool in_range(double v, const Range& r) const {
    return (r.lo_open ? v > r.lo : v >= r.lo) && v <= r.hi;
  }

  double number(const YAML::Node& n, const std::string& key, const Range& r) const {
    const std::string what = "a number in " + range_text(r);
    if (!n.IsScalar()) fail(n, key, what, text(n));
    std::string s = n.Scalar();
    double v;
    if (s == ".inf" || s == ".Inf" || s == ".INF" || s == "+.inf" || s == "+.Inf") {
      v = std::numeric_limits<double>::infinity();
    } else if (s == "-.inf" || s == "-.Inf" || s == "-.INF") {
      v = -std::numeric_limits<double>::infinity();
    } else {
      errno = 0;
      char* end = nullptr;
      v = std::strtod(s.c_str(), &end);
      // strtod also reads "nan", "inf" and hexadecimal: YAML numbers are none of these.
      const bool plain = s.find_first_not_of("0123456789+-.eE") == std::string::npos;
      if (s.empty() || *end != '\0' || errno == ERANGE || !plain || !std::isfinite(v))
        fail(n, key, what, s);
    }
    if (!in_range(v, r)) fail(n, key, what, s);
    return v;
  }

  long long whole(const YAML::Node& n, const std::string& key, const Range& r) const {
    const std::string what = "a whole number in " + range_text(r);
    if (!n.IsScalar()) fail(n, key, what, text(n));
    const std::string s = n.Scalar();
    errno = 0;
    char* end = nullptr;
    const long long v = std::strtoll(s.c_str(), &end, 10);
    if (s.empty() || *end != '\0' || errno == ERANGE ||
        s.find_first_not_of("0123456789+-") != std::string::npos ||
        !in_range(static_cast<double>(v), r))
      fail(n, key, what, s);
    return v;
  }

  std::string path_;
  std::vector<Level> levels_;
  std::size_t key_line_ = 0;  // of the key find() found last
};

YAML::Node parse_file(const std::string& path) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (!ec && size > kMaxConfigBytes)
    throw io::InputError(path, 0, "a configuration file of at most 1 MiB");
  try {
    return YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw io::InputError(path, 0, "a readable YAML configuration file");
  } catch (const YAML::ParserException& e) {
    throw io::InputError(path, static_cast<std::size_t>(e.mark.line) + 1,
                         "valid YAML (" + e.msg + ")");
  }
}

// The line of a dotted key in the file; of its deepest section the file has when the file does
// not set the key itself (0: none).
std::size_t line_of_key(const YAML::Node& root, const std::string& dotted) {
  YAML::Node node = root;
  std::size_t line = 0;
  std::istringstream parts(dotted);
  for (std::string part; std::getline(parts, part, '.');) {
    const auto entry = find_key(node, part);
    if (!entry) break;
    line = line_of(entry->first);
    node = entry->second;
  }
  return line;
}

}  // namespace

FileChoice read_file_choice(const std::string& path) {
  const YAML::Node root = parse_file(path);
  FileChoice choice;
  if (!root.IsMap()) return choice;  // load_configuration names the problem
  const Reader once(path, root);     // a key given twice is refused before either value counts
  for (const auto& kv : root) {
    if (!kv.first.IsScalar() || !kv.second.IsScalar()) continue;
    const std::string& name = kv.first.Scalar();
    const std::string& value = kv.second.Scalar();
    try {
      if (name == "method") {
        Method method;
        std::optional<ImageBaseline> image;
        parse_method_name(value, method, image);
        choice.method = value;
        choice.method_line = line_of(kv.first);
      } else if (name == "mode") {
        choice.mode = parse_mode(value);
        choice.mode_line = line_of(kv.first);
      }
    } catch (const std::invalid_argument&) {
      throw io::InputError(
          path, line_of(kv.second),
          std::string(name == "method" ? method_choices() : EnumNames<Mode>::kChoices) + " for " +
              name + ", got '" + value + "'");
    }
  }
  return choice;
}

Configuration load_configuration(const std::string& path, const std::string& method, Mode mode) {
  const YAML::Node root = parse_file(path);
  Configuration c = Configuration::defaults(method, mode);
  Reader reader(path, root);
  config_keys::visit(reader, c);
  reader.finish();
  if (method_name(c) != method || c.mode != mode) {
    throw std::logic_error(
        "load_configuration: the file's method or mode differs from the "
        "arguments (decide them with read_file_choice)");
  }
  try {
    validate(c);
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    const std::string key = message.substr(0, message.find(':'));
    throw io::InputError(path, line_of_key(root, key), "a consistent configuration: " + message);
  }
  return c;
}

std::size_t key_line(const std::string& path, const std::string& dotted_key) {
  return line_of_key(parse_file(path), dotted_key);
}

std::string configuration_yaml(const Configuration& c, const std::string& header,
                               bool with_method) {
  std::ostringstream out;
  std::istringstream lines(header);
  for (std::string line; std::getline(lines, line);) out << "# " << line << '\n';
  Configuration copy = c;
  Writer writer(out, with_method);
  config_keys::visit(writer, copy);
  return out.str();
}

void write_configuration(const std::string& path, const Configuration& c, const std::string& header,
                         bool with_method) {
  io::write_file_atomic(path, configuration_yaml(c, header, with_method));
}

}  // namespace loopscan
