#include <loopscan/io/incoming_ids.hpp>

#include <charconv>
#include <string_view>

#include <loopscan/io/errors.hpp>
#include <loopscan/io/line_reader.hpp>
#include <loopscan/io/parse_numbers.hpp>
#include <loopscan/io/text_file_writer.hpp>

namespace loopscan::io {

std::vector<int> read_incoming_ids(const std::string& path) {
  LineReader reader(path);
  std::vector<int> ids;
  std::string_view line;
  std::string_view token;
  while (next_data_line(reader, line)) {
    Tokenizer tokens(line);
    int id = 0;
    if (!tokens.next(token) || !parse_number(token, id) || !tokens.at_end() || id < 0) {
      throw InputError(path, reader.line_number(), "one non-negative integer keyframe id");
    }
    ids.push_back(id);
    check_record_count(reader, ids.size(), "keyframe ids");
  }
  return ids;
}

void write_incoming_ids(const std::string& path, const std::vector<int>& ids) {
  std::string text;
  text.reserve(ids.size() * 8);
  char buf[16];
  for (int id : ids) {
    const auto res = std::to_chars(buf, buf + sizeof(buf), id);
    text.append(buf, res.ptr);
    text.push_back('\n');
  }
  TextFileWriter writer(path);
  writer.write(text);
  writer.commit();
}

}  // namespace loopscan::io
