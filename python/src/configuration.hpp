#pragma once
// A configuration file (the CLI's --config) for the Python objects that take one.
#include <optional>
#include <string>

#include "loopscan/config/configuration.hpp"

namespace loopscan::python {

// The file's values over the defaults of its method and mode. `method` and `mode`, where given,
// must agree with the file's (where it sets them); otherwise the file's choice, else sc and
// default. `range_m`, where given, replaces imitation.range_m. Throws what load_configuration
// throws (the file, the line and the key) and std::invalid_argument on a disagreement.
Configuration load_python_configuration(const std::string& path,
                                        const std::optional<std::string>& method,
                                        const std::optional<std::string>& mode,
                                        const std::optional<double>& range_m);

}  // namespace loopscan::python
