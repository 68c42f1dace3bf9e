#pragma once
// The configuration as a YAML document (yaml-cpp): written with every key and its description,
// read back from a complete or partial file. A file may hold any subset of the keys; what it
// leaves out keeps the defaults of its method and mode. Unknown keys, duplicate keys, values of
// the wrong type and values out of range are refused with io::InputError naming the file, the
// line and the key ("my.yaml:12: expected a number in [0, 1] for
// closure.verification.min_overlap, got '1.5'").
#include <optional>
#include <string>

#include "loopscan/config/configuration.hpp"

namespace loopscan {

// The top-level `method` and `mode` of a file, if it sets them, with their lines.
struct FileChoice {
  std::optional<std::string> method;  // sc | m2dp | delight | bev | gist | bow
  std::optional<Mode> mode;
  std::size_t method_line = 0, mode_line = 0;
};
FileChoice read_file_choice(const std::string& path);

// Configuration::defaults(method, mode) with the file's values on top; then validate(), whose
// complaints name the file (and the key's line when the file sets it). A `method` or `mode` in
// the file must equal the arguments (decide them with read_file_choice first).
// `method`: sc | m2dp | delight | bev | gist | bow.
Configuration load_configuration(const std::string& path, const std::string& method, Mode mode);

// The line of a dotted key ("closure.candidates") in the file; of its deepest section the file
// has when the file does not set the key itself; 0 when it has none of them.
std::size_t key_line(const std::string& path, const std::string& dotted_key);

// Every key with its value and description; `header` (comment lines without '#') goes first.
// Without `with_method` the file leaves the method out (what run and demo used: every method).
std::string configuration_yaml(const Configuration& c, const std::string& header = "",
                               bool with_method = true);

// configuration_yaml written atomically (temp file, rename).
void write_configuration(const std::string& path, const Configuration& c,
                         const std::string& header = "", bool with_method = true);

}  // namespace loopscan
