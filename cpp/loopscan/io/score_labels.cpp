#include "loopscan/io/score_labels.hpp"

#include "loopscan/io/errors.hpp"
#include "loopscan/io/line_reader.hpp"
#include "loopscan/io/parse_numbers.hpp"

namespace loopscan::io {

std::vector<eval::ScoreLabel> read_score_labels(const std::string& path) {
  constexpr const char* kExpected =
      "`score label`: a finite score (higher = more similar), then the label 0 or 1";
  LineReader reader(path);
  std::vector<eval::ScoreLabel> pairs;
  std::string_view line;
  double v[2];
  while (next_data_line(reader, line)) {
    Tokenizer tokens(line);
    parse_exactly(reader, tokens, v, 2, kExpected, 1e300);
    if (v[1] != 0.0 && v[1] != 1.0) throw InputError(path, reader.line_number(), kExpected);
    pairs.push_back({v[0], static_cast<int>(v[1])});
    check_record_count(reader, pairs.size(), "pairs");
  }
  return pairs;
}

}  // namespace loopscan::io
