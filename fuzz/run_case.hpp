#pragma once
// One fuzz case, run: the reader in-process, or the `loopscan` CLI on the case's files.
#include <filesystem>
#include <string>

#include "fuzz_target.hpp"

namespace loopscan::fuzz {

// Outcomes: 0 accepted, 1 rejected cleanly (io::InputError, std::invalid_argument / exit code
// 2), 2 a finding (described in `what`).
int run_reader(const Target& t, const std::filesystem::path& dir, std::string& what);

// `cli` with t.command's arguments on the files in `dir`: exit code 0 or 2 are outcomes 0 and
// 1; anything else (1, a signal, a sanitizer abort, running past `hang_seconds`) is a finding,
// with the command's output (kept in <dir>/../cli.txt) in `what`.
int run_command(const std::string& cli, double hang_seconds, const Target& t,
                const std::filesystem::path& dir, const std::filesystem::path& out, long variant,
                std::string& what);

}  // namespace loopscan::fuzz
