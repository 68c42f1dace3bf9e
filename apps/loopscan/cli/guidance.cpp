#include "cli/guidance.hpp"

#include <algorithm>

#include "loopscan/io/errors.hpp"

namespace loopscan::cli {
namespace {

// Lists of values also split at commas, unless the option chose its own delimiter (free text
// such as legend names, which may contain commas).
void comma_lists(CLI::App* app) {
  for (CLI::Option* o : app->get_options()) {
    if (o->get_items_expected_max() > 1 && o->get_delimiter() == '\0') o->delimiter(',');
  }
  for (CLI::App* sub : app->get_subcommands({})) comma_lists(sub);
}

}  // namespace

void accept_comma_lists(CLI::App& app) { comma_lists(&app); }

std::string unknown_command(const CLI::App& app, int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') return "";
  const std::string word = argv[1];
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    if (sub->get_name() == word) return "";
    names.push_back(sub->get_name());
  }
  std::string message = "unknown command '" + word + "'";
  const std::string guess = io::closest_name(word, names);
  if (!guess.empty()) message += " (did you mean '" + guess + "'?)";
  message += "; commands:";
  for (const std::string& n : names) message += " " + n;
  return message;
}

std::string suggest_option(const CLI::App& app) {
  const CLI::App* parsing = &app;
  std::vector<std::string> unexpected = app.remaining();
  for (;;) {  // the deepest subcommand given on the line
    const std::vector<CLI::App*> used = parsing->get_subcommands();
    if (used.empty()) break;
    parsing = used.back();
    for (const std::string& r : parsing->remaining()) unexpected.push_back(r);
  }
  std::vector<std::string> names;
  for (const CLI::Option* o : parsing->get_options()) {
    for (const std::string& n : o->get_lnames()) names.push_back("--" + n);
  }
  for (const std::string& word : unexpected) {
    if (word.rfind("--", 0) != 0) continue;
    const std::string guess = io::closest_name(word.substr(0, word.find('=')), names);
    if (!guess.empty()) return "unknown option " + word + " (did you mean " + guess + "?)";
  }
  return "";
}

}  // namespace loopscan::cli
