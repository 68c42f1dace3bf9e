#include "fuzz_target.hpp"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>

namespace loopscan::fuzz {

Target single_file(const std::string& name, const std::string& file, Format format,
                   std::vector<std::string> seeds,
                   std::function<void(const std::string&)> read_file) {
  Target t;
  t.name = name;
  t.format = format;
  for (std::string& s : seeds) t.seeds.push_back({{file, std::move(s)}});
  t.read = [file, read_file](const std::string& dir) { read_file(dir + "/" + file); };
  return t;
}

std::string bytes_written_by(const std::function<void(const std::string& path)>& write) {
  const std::string tmp = (std::filesystem::temp_directory_path() /
                           ("loopscan_fuzz_seed_" + std::to_string(::getpid())))
                              .string();
  write(tmp);
  std::ifstream in(tmp, std::ios::binary);
  std::string bytes{std::istreambuf_iterator<char>(in), {}};
  std::filesystem::remove(tmp);
  return bytes;
}

}  // namespace loopscan::fuzz
