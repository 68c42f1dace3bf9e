#pragma once
// Fast line-by-line reading of text files, gzip-compressed or not.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

struct gzFile_s;  // zlib handle; opaque here so zlib stays a private dependency

namespace loopscan::io {

// Reads a text file line by line. Files are opened through zlib, which inflates gzip data
// (e.g. "*.gz") and passes plain text through unchanged. Throws InputError(path, 0,
// "a readable file") when the file cannot be opened, and InputError on corrupt or truncated
// gzip data and on a line longer than io::limits::kMaxLineBytes (so /dev/zero or a binary
// file given as text ends in an error, not in unbounded memory).
class LineReader {
 public:
  explicit LineReader(const std::string& path);
  ~LineReader();
  LineReader(LineReader&& other) noexcept;
  LineReader& operator=(LineReader&& other) noexcept;
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;

  // Next line without its "\n" / "\r\n" terminator; false at end of file. The view is valid
  // until the next call.
  bool next(std::string_view& line);
  // 1-based number of the line last returned by next() (0 before the first call).
  std::size_t line_number() const { return line_number_; }
  const std::string& path() const { return path_; }

 private:
  bool refill();  // false when no more input
  void close();

  std::string path_;
  gzFile_s* file_ = nullptr;
  std::vector<char> buf_;
  std::size_t begin_ = 0;    // start of the unread data
  std::size_t scanned_ = 0;  // bytes after begin_ already known to hold no '\n'
  std::size_t end_ = 0;      // end of the valid data
  std::size_t line_number_ = 0;
  bool eof_ = false;
};

// next() for data files, where blank (whitespace-only) lines may only trail the data: skips
// them at the end of the file, throws InputError naming the first blank line when data follows.
bool next_data_line(LineReader& reader, std::string_view& line);

}  // namespace loopscan::io
