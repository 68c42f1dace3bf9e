#pragma once
// Subcommands of the `loopscan` CLI. Each registers its flags and a callback; the callbacks
// throw io::InputError / std::invalid_argument on bad input (exit code 2, see main.cpp).
#include <CLI/CLI.hpp>

namespace loopscan::cli {

void add_describe_command(CLI::App& app);
void add_evaluate_command(CLI::App& app);
void add_pairs_command(CLI::App& app);
void add_plot_command(CLI::App& app);
void add_demo_command(CLI::App& app);
void add_simulate_command(CLI::App& app);
void add_db_command(CLI::App& app);
void add_render_command(CLI::App& app);
void add_vo_command(CLI::App& app);
void add_run_command(CLI::App& app);
void add_vocab_command(CLI::App& app);
void add_close_command(CLI::App& app);
void add_slam_command(CLI::App& app);
void add_config_command(CLI::App& app);

}  // namespace loopscan::cli
