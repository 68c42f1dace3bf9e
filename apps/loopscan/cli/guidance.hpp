#pragma once
// What the CLI says when a command line is wrong: the closest valid subcommand or option
// ("did you mean"), and comma-separated lists wherever an option takes several values.
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace loopscan::cli {

// Every option of `app` and its subcommands that takes several values also accepts them
// comma-separated (`--methods sc,m2dp` as well as `--methods sc m2dp`).
void accept_comma_lists(CLI::App& app);

// "unknown command 'describ' (did you mean 'describe'?)" when argv[1] is a word that is no
// subcommand of `app`; "" otherwise.
std::string unknown_command(const CLI::App& app, int argc, char** argv);

// For arguments CLI11 did not expect: "unknown option --methdo (did you mean --method?)" with
// the closest option of the subcommand being parsed, or "".
std::string suggest_option(const CLI::App& app);

}  // namespace loopscan::cli
