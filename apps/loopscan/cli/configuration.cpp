#include "cli/configuration.hpp"

#include <filesystem>
#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "loopscan/io/errors.hpp"

namespace loopscan::cli {
namespace {

struct Vote {
  std::string value;
  std::string where;  // "--mode", "my.yaml:2", "sc/config.yaml"
};

// The value every vote names, or "" without votes; different values are refused naming both.
std::string agreed(const char* what, const std::vector<Vote>& votes) {
  for (const Vote& v : votes) {
    if (v.value != votes.front().value) {
      throw std::invalid_argument(std::string("conflicting ") + what + "s: " + votes.front().where +
                                  " says " + votes.front().value + ", " + v.where + " says " +
                                  v.value);
    }
  }
  return votes.empty() ? "" : votes.front().value;
}

Described from_timing(const std::string& path) {
  std::ifstream in(path);
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception&) {
    throw io::InputError(path, 0, "a JSON object (the timing of a describe run)");
  }
  Described d;
  d.source = path;
  const auto text = [&](const char* key) -> std::optional<std::string> {
    if (!j.is_object() || !j.contains(key)) return std::nullopt;
    if (!j[key].is_string()) throw io::InputError(path, 0, std::string("a string for ") + key);
    return j[key].get<std::string>();
  };
  try {
    d.method = text("method");
    if (const auto mode = text("mode")) d.mode = parse_mode(*mode);
    if (const auto frame = text("frame")) d.frame = parse_descriptor_frame(*frame);
  } catch (const std::invalid_argument& e) {
    throw io::InputError(path, 0, std::string("a described set's metadata: ") + e.what());
  }
  return d;
}

}  // namespace

void add_config_option(CLI::App& cmd, ConfigFlags& flags) {
  cmd.add_option("--config", flags.file,
                 "YAML file of tuning parameters (partial files allowed; `loopscan config` "
                 "prints every key)");
}

void add_mode_option(CLI::App& cmd, ConfigFlags& flags) {
  cmd.add_option("--mode", flags.mode,
                 "default | reference (the paper's code); default: the inputs' own, else default")
      ->check(CLI::IsMember({"default", "reference"}));
}

Described read_described(const std::string& path) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(path)) return {};
  const std::string config = path + "/config.yaml";
  if (fs::exists(config)) {
    const FileChoice choice = read_file_choice(config);
    Described d;
    d.source = config;
    d.method = choice.method;
    d.mode = choice.mode;
    if (d.method && d.mode) {
      const Configuration c = load_configuration(config, *d.method, *d.mode);
      if (!c.image_baseline) d.frame = descriptor_frame(c.method, sequence_options(c).descriptors);
      if (!c.image_baseline && c.method == Method::BirdsEye) d.birds_eye = c.descriptors.birds_eye;
    }
    return d;
  }
  const std::string timing = path + "/timing.json";
  if (fs::exists(timing)) return from_timing(timing);
  return {};
}

Described described_map(const std::string& path, const DatabaseConfig& map) {
  Described d;
  d.source = path;
  d.method = method_name(map.method);
  d.mode = map.mode;
  d.frame = map.frame;
  if (map.method == Method::BirdsEye) d.birds_eye = map.birds_eye;
  return d;
}

std::optional<DescriptorFrame> described_frame(const std::vector<Described>& described) {
  std::vector<Vote> votes;
  for (const Described& d : described)
    if (d.frame) votes.push_back({descriptor_frame_name(*d.frame), d.source});
  const std::string frame = agreed("descriptor frame", votes);
  if (frame.empty()) return std::nullopt;
  return parse_descriptor_frame(frame);
}

Configuration resolve_configuration(const ConfigFlags& flags,
                                    const std::vector<Described>& described,
                                    const std::string& fallback_method) {
  std::vector<Vote> methods, modes;
  if (!flags.method.empty()) methods.push_back({flags.method, "--method"});
  if (!flags.mode.empty()) modes.push_back({flags.mode, "--mode"});
  if (!flags.file.empty()) {
    const FileChoice choice = read_file_choice(flags.file);
    const std::string at = flags.file + ":";
    if (choice.method) methods.push_back({*choice.method, at + std::to_string(choice.method_line)});
    if (choice.mode)
      modes.push_back({mode_name(*choice.mode), at + std::to_string(choice.mode_line)});
  }
  for (const Described& d : described) {
    if (d.method) methods.push_back({*d.method, d.source});
    if (d.mode) modes.push_back({mode_name(*d.mode), d.source});
  }
  std::string method = agreed("method", methods);
  if (method.empty()) method = fallback_method;
  if (method.empty()) {
    throw std::invalid_argument(
        "--method: no input says which method described it (no config.yaml or timing.json, no "
        "`method` in --config)");
  }
  std::string mode_text = agreed("mode", modes);
  const Mode mode = mode_text.empty() ? Mode::Default : parse_mode(mode_text);
  described_frame(described);  // described sets in different frames do not compare
  Configuration c = flags.file.empty() ? Configuration::defaults(method, mode)
                                       : load_configuration(flags.file, method, mode);
  // Bird's-eye places are matched in the layout they were described with.
  const Described* layout = nullptr;
  for (const Described& d : described) {
    if (!d.birds_eye) continue;
    if (layout && !same_layout(*d.birds_eye, *layout->birds_eye)) {
      throw std::invalid_argument("bird's-eye places of " + layout->source + " and " + d.source +
                                  " differ in cell_m, range_m, taper_start_m, taper_end_m, "
                                  "rings or angles, or in the cell kind: they do not compare");
    }
    layout = &d;
  }
  if (layout) c.descriptors.birds_eye = *layout->birds_eye;
  return c;
}

void require_loop_closing(const Configuration& c, const ConfigFlags& flags) {
  try {
    validate_loop_closing(c);
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    const std::string key = message.substr(0, message.find(':'));
    const std::size_t line = flags.file.empty() ? 0 : key_line(flags.file, key);
    if (line == 0) throw;
    throw io::InputError(flags.file, line, "a configuration for loop closing: " + message);
  }
}

void write_used_configuration(const std::string& dir, const Configuration& c, bool with_method) {
  std::filesystem::create_directories(dir);
  write_configuration(dir + "/config.yaml", c,
                      "The configuration these outputs were made with (loopscan " +
                          std::string(LOOPSCAN_VERSION) +
                          "); `--config` takes it back.\n`loopscan config` prints every key "
                          "with its description.",
                      with_method);
}

}  // namespace loopscan::cli
