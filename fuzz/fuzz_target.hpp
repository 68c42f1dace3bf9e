#pragma once
// A reader under fuzzing: valid seed inputs made in-process (no files needed), the file name
// each input is written to, and the call that reads them back. An input is a set of files
// (most readers take one); the mutator changes one of them per case.
#include <functional>
#include <map>
#include <random>
#include <string>
#include <vector>

namespace loopscan::fuzz {

using Files = std::map<std::string, std::string>;  // file name -> bytes

enum class Format { Text, Binary };

struct Target {
  std::string name;
  Format format = Format::Text;
  // Where the CRC-32 of a binary file lives: the last 4 bytes (recomputed after some
  // mutations, so that the value checks behind the checksum are reached too), or none.
  bool trailing_crc = false;
  bool png_chunks = false;    // PNG: chunk CRCs recomputed the same way
  bool noisy_stderr = false;  // its library warns on stderr (libjpeg): captured per case
  std::vector<Files> seeds;   // valid inputs
  std::string mutated_file;   // the file of a seed that cases mutate ("" = the only one)
  // Reads the input in `dir`; throws io::InputError or std::invalid_argument on bad input.
  std::function<void(const std::string& dir)> read;
  // --cli mode instead: the `loopscan` arguments that read the input in `dir` and write to
  // `out`; `variant` (the case number) may choose among methods.
  std::function<std::vector<std::string>(const std::string& dir, const std::string& out,
                                         long variant)>
      command;
};

// A target reading one file: `read_file(dir + "/" + file)` on each seed's bytes.
Target single_file(const std::string& name, const std::string& file, Format format,
                   std::vector<std::string> seeds,
                   std::function<void(const std::string&)> read_file);

// The bytes a writer puts in a file (the library's own writers make the seeds).
std::string bytes_written_by(const std::function<void(const std::string& path)>& write);

// Every reader of loopscan that takes a file from a user (targets_text.cpp, targets_binary.cpp).
std::vector<Target> text_targets();
std::vector<Target> binary_targets();
// The CLI commands that read user files, whole (exit code 0 or 2 expected): targets_cli.cpp.
std::vector<Target> cli_targets();

}  // namespace loopscan::fuzz
