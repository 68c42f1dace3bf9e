#pragma once
// Every writing command's outputs go through one io::OutputSet: written into a staging
// directory and swapped in at the end, under a lock (see io/output_set.hpp).
#include <functional>
#include <memory>
#include <string>

#include <CLI/CLI.hpp>

#include "loopscan/io/output_set.hpp"

namespace loopscan::cli {

// The command line, kept for the `.loopscan` marker of every output set (set by main).
void set_command_line(int argc, char** argv);
const std::string& command_line();

void register_staging(const std::string& staging, const std::string& target);
void unregister_staging(const std::string& staging);

// Runs `body()` with `out` pointing at the staging directory of the set at `out`, then
// commits it and restores `out`. shown() maps staging paths back for messages.
template <typename Body>
void with_output_dir(std::string& out, Body body) {
  io::OutputSet set(out, io::OutputSet::Kind::Directory, command_line());
  const std::string target = out;
  out = set.path();
  register_staging(out, target);
  try {
    body();
  } catch (...) {
    unregister_staging(set.path());
    out = target;
    throw;
  }
  unregister_staging(set.path());
  out = target;
  set.commit();
}

// The same lock and leftover cleaning for a command whose output is one file: `body()` runs
// with `out` set to the resolved target (links followed). An existing file is only replaced
// when `is_ours(path)` recognises it (e.g. by its magic).
template <typename Body>
void with_output_file(std::string& out, const std::function<bool(const std::string&)>& is_ours,
                      Body body) {
  io::OutputSet set(out, io::OutputSet::Kind::File, command_line(), is_ours);
  const std::string given = out;
  out = set.path();
  try {
    body();
  } catch (...) {
    out = given;
    throw;
  }
  out = given;
  set.commit();
}

// True when the file at `path` starts with `magic` (for with_output_file's `is_ours`).
bool starts_with_bytes(const std::string& path, const std::string& magic);

// Refuses (std::invalid_argument) when an input named on the command line lies inside the
// output directory `out`, which the new set would replace as a whole.
void refuse_inputs_inside(const CLI::App& cmd, const std::string& out);

// The usual callback of a command writing a directory: `run(args)` with args.out redirected
// into the staging directory of the set.
template <typename Args>
void run_writing_dir(CLI::App* cmd, const std::shared_ptr<Args>& args, void (*run)(const Args&)) {
  cmd->callback([cmd, args, run] {
    Args a = *args;
    refuse_inputs_inside(*cmd, a.out);
    with_output_dir(a.out, [&] { run(a); });
  });
}

// A path as the user named it: an open set's staging directory replaced by its target.
std::string shown(const std::string& path);

}  // namespace loopscan::cli
