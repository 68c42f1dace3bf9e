#pragma once
// Checks on SVG text shared by the report tests: well-formedness, element counts, path data.
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

namespace loopscan::test {

// Tiny XML check: balanced, properly nested tags and only the five predefined entities.
inline std::string xml_problem(const std::string& s) {
  std::vector<std::string> stack;
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '&') {
      bool known = false;
      for (const char* e : {"&amp;", "&lt;", "&gt;", "&quot;", "&apos;"})
        known = known || s.compare(i, std::string(e).size(), e) == 0;
      if (!known) return "bad entity at " + std::to_string(i);
    }
    if (s[i] == '>') return "stray '>' at " + std::to_string(i);
    if (s[i] != '<') continue;
    if (s.compare(i, 2, "<?") == 0 || s.compare(i, 4, "<!--") == 0) {
      const std::size_t end = s.find(s[i + 1] == '?' ? "?>" : "-->", i);
      if (end == std::string::npos) return "unterminated declaration";
      i = end + 1;
      continue;
    }
    std::size_t j = i + 1;
    char quote = 0;
    for (; j < s.size() && (quote || s[j] != '>'); ++j) {
      if (s[j] == '<' && !quote) return "'<' inside tag at " + std::to_string(j);
      if (s[j] == '"' || s[j] == '\'') quote = (quote == s[j]) ? 0 : (quote ? quote : s[j]);
    }
    if (j >= s.size()) return "unterminated tag";
    const std::string body = s.substr(i + 1, j - i - 1);
    const bool closing = body[0] == '/';
    const std::string name = body.substr(closing, body.find_first_of(" /\n", 1) - closing);
    if (closing) {
      if (stack.empty() || stack.back() != name) return "unexpected </" + name + ">";
      stack.pop_back();
    } else if (body.back() != '/') {
      stack.push_back(name);
    }
    i = j;
  }
  return stack.empty() ? "" : "unclosed <" + stack.back() + ">";
}

inline std::size_t count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

// The d attributes of all <path> elements, in order.
inline std::vector<std::string> path_data(const std::string& svg) {
  std::vector<std::string> out;
  for (std::size_t p = svg.find("<path d=\""); p != std::string::npos;
       p = svg.find("<path d=\"", p + 1)) {
    const std::size_t start = p + 9;
    out.push_back(svg.substr(start, svg.find('"', start) - start));
  }
  return out;
}

// (x, y) pairs of M/L commands.
inline std::vector<std::pair<double, double>> line_points(const std::string& d) {
  std::vector<std::pair<double, double>> pts;
  const char* c = d.c_str();
  while (*c) {
    if (*c == 'M' || *c == 'L') {
      char* end = nullptr;
      const double x = std::strtod(c + 1, &end);
      const double y = std::strtod(end + 1, &end);  // skip ','
      pts.emplace_back(x, y);
      c = end;
    } else {
      ++c;
    }
  }
  return pts;
}

}  // namespace loopscan::test
