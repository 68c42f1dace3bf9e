#include "cli/guidance.hpp"

#include <algorithm>

namespace loopscan::cli {
namespace {

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// Lists of values also split at commas, unless the option chose its own delimiter (free text
// such as legend names, which may contain commas).
void comma_lists(CLI::App* app) {
  for (CLI::Option* o : app->get_options()) {
    if (o->get_items_expected_max() > 1 && o->get_delimiter() == '\0') o->delimiter(',');
  }
  for (CLI::App* sub : app->get_subcommands({})) comma_lists(sub);
}

}  // namespace

std::string closest(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(2, word.size() / 3) + 1;
  for (const std::string& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best_distance || (c.rfind(word, 0) == 0 && word.size() >= 3 && best.empty())) {
      best_distance = std::min(d, best_distance);
      best = c;
    }
  }
  return best;
}

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
  const std::string guess = closest(word, names);
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
    const std::string guess = closest(word.substr(0, word.find('=')), names);
    if (!guess.empty()) return "unknown option " + word + " (did you mean " + guess + "?)";
  }
  return "";
}

}  // namespace loopscan::cli
