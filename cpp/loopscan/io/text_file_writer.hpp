#pragma once
// Atomic text output, gzip-compressed when the path ends in ".gz".
#include <memory>
#include <string>
#include <string_view>

#include <loopscan/io/atomic_file.hpp>

namespace loopscan::io {

// Buffers text into an AtomicWriter; with a ".gz" path the bytes are gzip-compressed so the
// output is readable by zcat and by LineReader alike. Nothing appears at `path` until commit().
class TextFileWriter {
 public:
  explicit TextFileWriter(const std::string& path);
  ~TextFileWriter();
  TextFileWriter(const TextFileWriter&) = delete;
  TextFileWriter& operator=(const TextFileWriter&) = delete;

  void write(std::string_view text);
  // Finishes compression and atomically replaces `path`; throws std::runtime_error on failure.
  void commit();

 private:
  struct Gzip;
  AtomicWriter out_;
  std::unique_ptr<Gzip> gzip_;  // null for plain text
};

// True when `path` ends in ".gz".
bool has_gz_suffix(const std::string& path);

}  // namespace loopscan::io
