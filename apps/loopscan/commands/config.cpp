// loopscan config: every tuning parameter with its default for a method and mode, as the YAML
// document `--config` takes (partially or whole).
#include <cstdio>

#include "cli/commands.hpp"
#include "cli/configuration.hpp"
#include "cli/output_sets.hpp"

namespace loopscan::cli {
namespace {

struct ConfigArgs {
  ConfigFlags config;
  std::string out;
};

void run_config(const ConfigArgs& a) {
  const Configuration c = resolve_configuration(a.config);
  const std::string header =
      "loopscan " + std::string(LOOPSCAN_VERSION) + ": the defaults of " + method_name(c) + ", " +
      mode_name(c.mode) + " mode" + (a.config.file.empty() ? "" : ", with " + a.config.file) +
      ".\nGive any subset of these keys in a file to --config; what it leaves out keeps its "
      "default.";
  if (a.out.empty()) {
    std::fputs(configuration_yaml(c, header).c_str(), stdout);
    return;
  }
  // An existing file is only replaced when it is a configuration loopscan wrote.
  std::string out = a.out;
  const auto is_ours = [](const std::string& p) { return starts_with_bytes(p, "# loopscan"); };
  with_output_file(out, is_ours, [&] { write_configuration(out, c, header); });
  std::printf("%s, %s mode -> %s\n", method_name(c).c_str(), mode_name(c.mode).c_str(),
              a.out.c_str());
}

}  // namespace

void add_config_command(CLI::App& app) {
  auto a = std::make_shared<ConfigArgs>();
  CLI::App* cmd = app.add_subcommand(
      "config", "Print every tuning parameter with its default (the YAML --config takes)");
  cmd->add_option("--method", a->config.method, "sc | m2dp | delight | bev | gist | bow (default: sc)");
  add_mode_option(*cmd, a->config);
  cmd->get_option("--mode")->description("default | reference (default: the file's, else default)");
  add_config_option(*cmd, a->config);
  cmd->get_option("--config")->description("a configuration file to apply first (to check it)");
  cmd->add_option("--out", a->out, "write the YAML to this file instead of standard output");
  cmd->callback([a] { run_config(*a); });
}

}  // namespace loopscan::cli
