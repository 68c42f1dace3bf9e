#pragma once
// A command's configuration: `--config FILE` over the defaults of its method and mode, where the
// method and the mode come from the flags, the file's own `method` / `mode` keys and the
// metadata of the described sets or maps the command reads. They must agree: a contradiction
// is refused (exit code 2) naming both values and where each came from.
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "loopscan/config/config_file.hpp"

namespace loopscan::cli {

// The flags that decide a command's configuration ("" = not given).
struct ConfigFlags {
  std::string file;    // --config
  std::string method;  // --method: sc | m2dp | delight (| gist | bow where the command takes them)
  std::string mode;    // --mode: default | reference
};

// --config FILE on `cmd`.
void add_config_option(CLI::App& cmd, ConfigFlags& flags);
// --mode default|reference on `cmd` (no default: the described sets' or the file's, else default).
void add_mode_option(CLI::App& cmd, ConfigFlags& flags);

// What a described set or a map says of how its places were described.
struct Described {
  std::string source;                 // the file that said it (config.yaml, timing.json, map.db)
  std::optional<std::string> method;  // sc | m2dp | delight | bev | gist | bow
  std::optional<Mode> mode;
  std::optional<DescriptorFrame> frame;
  std::optional<BirdsEyePlaceConfig> birds_eye;  // bev: the places' layout
};

// A `describe` output directory: its config.yaml (the configuration it was described with),
// else its timing.json. A signature file, or a directory without either, says nothing.
Described read_described(const std::string& path);
// A place database: its method, and its mode and frame when the file records them.
Described described_map(const std::string& path, const DatabaseConfig& map);

// Resolves the method (flag, file, described sets; else `fallback_method`, "" to require one of
// them) and the mode (else
// default), then loads the configuration (Configuration::defaults when there is no file).
// `described` sets must agree with each other too; their frames must agree with each other.
Configuration resolve_configuration(const ConfigFlags& flags,
                                    const std::vector<Described>& described = {},
                                    const std::string& fallback_method = "sc");

// validate_loop_closing, its complaint naming the --config file and line when the file set the key.
void require_loop_closing(const Configuration& c, const ConfigFlags& flags);

// The frame the described sets agree on (nullopt when none says).
std::optional<DescriptorFrame> described_frame(const std::vector<Described>& described);

// Writes `c` as DIR/config.yaml: the configuration a command's outputs were made with (run and
// demo: without the method, they use every one).
void write_used_configuration(const std::string& dir, const Configuration& c,
                              bool with_method = true);

}  // namespace loopscan::cli
