// loopscan: place recognition for stereo visual odometry with LiDAR-style descriptors.
#include <cstdio>
#include <stdexcept>

#include "cli/commands.hpp"
#include "cli/guidance.hpp"
#include "cli/output_sets.hpp"
#include "loopscan/io/errors.hpp"

int main(int argc, char** argv) {
  loopscan::cli::set_command_line(argc, argv);
  CLI::App app{"loopscan: fast, robust place recognition for stereo visual odometry", "loopscan"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("loopscan ") + LOOPSCAN_VERSION);
  loopscan::cli::add_describe_command(app);
  loopscan::cli::add_evaluate_command(app);
  loopscan::cli::add_pairs_command(app);
  loopscan::cli::add_plot_command(app);
  loopscan::cli::add_simulate_command(app);
  loopscan::cli::add_demo_command(app);
  loopscan::cli::add_db_command(app);
  loopscan::cli::add_render_command(app);
  loopscan::cli::add_vo_command(app);
  loopscan::cli::add_run_command(app);
  loopscan::cli::add_vocab_command(app);
  loopscan::cli::add_close_command(app);
  loopscan::cli::add_slam_command(app);
  loopscan::cli::add_config_command(app);
  loopscan::cli::accept_comma_lists(app);
  if (const std::string unknown = loopscan::cli::unknown_command(app, argc, argv);
      !unknown.empty()) {
    std::fprintf(stderr, "error: %s\n", unknown.c_str());
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // An unknown option is named with the closest valid one, even when CLI11 first complains
    // about a required option the misspelling left out.
    const std::string guess = loopscan::cli::suggest_option(app);
    if (!guess.empty()) {
      std::fprintf(stderr, "error: %s\nRun with --help for more information.\n", guess.c_str());
      return 2;
    }
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  } catch (const loopscan::io::InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
