#include "configuration.hpp"

#include <stdexcept>

#include "loopscan/config/config_file.hpp"

namespace loopscan::python {

Configuration load_python_configuration(const std::string& path,
                                        const std::optional<std::string>& method,
                                        const std::optional<std::string>& mode,
                                        const std::optional<double>& range_m) {
  const FileChoice file = read_file_choice(path);
  const std::string m = method.value_or(file.method.value_or("sc"));
  const Mode d = mode ? parse_mode(*mode) : file.mode.value_or(Mode::Default);
  if (file.method && *file.method != m) {
    throw std::invalid_argument(path + ":" + std::to_string(file.method_line) +
                                ": the file is for method " + *file.method +
                                ", the argument asks for " + m);
  }
  if (file.mode && *file.mode != d) {
    throw std::invalid_argument(path + ":" + std::to_string(file.mode_line) +
                                ": the file's mode differs from the argument's");
  }
  Configuration c = load_configuration(path, m, d);
  if (range_m) {
    c.imitation.range_m = *range_m;
    validate(c);
  }
  return c;
}

}  // namespace loopscan::python
