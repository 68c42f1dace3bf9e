#include "loopscan/io/bow_file.hpp"

#include <cmath>
#include <sstream>

#include "loopscan/io/atomic_file.hpp"
#include "loopscan/io/errors.hpp"
#include "loopscan/io/limits.hpp"
#include "loopscan/io/line_reader.hpp"
#include "loopscan/io/parse_numbers.hpp"

namespace loopscan::io {

void write_bow_vectors(const std::string& path, const std::vector<SparseVector>& vectors) {
  std::ostringstream s;
  s.precision(9);
  for (const SparseVector& v : vectors) {
    for (std::size_t i = 0; i < v.size(); ++i)
      s << (i ? " " : "") << v[i].first << ' ' << v[i].second;
    s << '\n';
  }
  write_file_atomic(path, s.str());
}

std::vector<SparseVector> read_bow_vectors(const std::string& path) {
  LineReader reader(path);
  std::string_view line;
  std::vector<SparseVector> out;
  const std::string expected = "`word weight` pairs: word ids increasing from 0 (at most " +
                               std::to_string(limits::kMaxWordId) + "), weights finite and > 0";
  while (reader.next(line)) {
    SparseVector v;
    Tokenizer t(line);
    std::string_view tok;
    while (t.next(tok)) {
      int word = 0;
      float weight = 0;
      if (!parse_number(tok, word) || word < 0 || word > limits::kMaxWordId ||
          (!v.empty() && word <= v.back().first) || !t.next(tok) || !parse_number(tok, weight) ||
          !std::isfinite(weight) || weight <= 0) {
        throw InputError(path, reader.line_number(), expected);
      }
      v.emplace_back(word, weight);
    }
    out.push_back(std::move(v));
    check_record_count(reader, out.size(), "places");
  }
  return out;
}

}  // namespace loopscan::io
