#include <loopscan/io/text_file_writer.hpp>

#include <zlib.h>

#include <algorithm>
#include <climits>
#include <stdexcept>
#include <vector>

#include "loopscan/io/file_names.hpp"

namespace loopscan::io {

struct TextFileWriter::Gzip {
  z_stream strm{};
  std::vector<char> buf = std::vector<char>(std::size_t{1} << 18);

  Gzip() {
    // windowBits 15 + 16 selects the gzip wrapper (not raw zlib), as gzip/zcat expect.
    if (deflateInit2(&strm, Z_DEFAULT_COMPRESSION, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) !=
        Z_OK) {
      throw std::runtime_error("zlib deflateInit2 failed");
    }
  }
  ~Gzip() { deflateEnd(&strm); }
  Gzip(const Gzip&) = delete;
  Gzip& operator=(const Gzip&) = delete;

  // Feeds `size` bytes (possibly 0 with Z_FINISH) and writes the compressed output to `os`.
  void pump(const char* data, std::size_t size, int flush, std::ostream& os,
            const std::string& path) {
    do {
      const std::size_t chunk = std::min<std::size_t>(size, UINT_MAX);
      strm.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data));
      strm.avail_in = static_cast<uInt>(chunk);
      const int chunk_flush = chunk == size ? flush : Z_NO_FLUSH;
      int ret = Z_OK;
      do {
        strm.next_out = reinterpret_cast<Bytef*>(buf.data());
        strm.avail_out = static_cast<uInt>(buf.size());
        ret = deflate(&strm, chunk_flush);
        if (ret == Z_STREAM_ERROR) throw std::runtime_error("cannot write '" + path + "': zlib");
        os.write(buf.data(), static_cast<std::streamsize>(buf.size() - strm.avail_out));
      } while (strm.avail_out == 0 || (chunk_flush == Z_FINISH && ret != Z_STREAM_END));
      data += chunk;
      size -= chunk;
    } while (size > 0);
  }
};

bool has_gz_suffix(const std::string& path) { return ends_with(path, ".gz"); }

TextFileWriter::TextFileWriter(const std::string& path) : out_(path) {
  if (has_gz_suffix(path)) gzip_ = std::make_unique<Gzip>();
}

TextFileWriter::~TextFileWriter() = default;

void TextFileWriter::write(std::string_view text) {
  if (gzip_) {
    gzip_->pump(text.data(), text.size(), Z_NO_FLUSH, out_.stream(), out_.path());
  } else {
    out_.stream().write(text.data(), static_cast<std::streamsize>(text.size()));
  }
}

void TextFileWriter::commit() {
  if (gzip_) gzip_->pump(nullptr, 0, Z_FINISH, out_.stream(), out_.path());
  out_.commit();
}

}  // namespace loopscan::io
