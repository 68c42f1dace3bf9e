// loopscan plot: columns of a CSV file with a header (pr.csv, timing tables, sweeps) -> an SVG
// line plot, so that figures come from our outputs without numpy or matplotlib.
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "cli/commands.hpp"
#include "cli/options.hpp"
#include "cli/output_sets.hpp"
#include "loopscan/io/atomic_file.hpp"
#include "loopscan/io/errors.hpp"
#include "loopscan/io/line_reader.hpp"
#include "loopscan/io/parse_numbers.hpp"
#include "loopscan/report/plot.hpp"

namespace loopscan::cli {
namespace {

struct PlotArgs {
  std::string csv, x, out, title, x_label, y_label;
  std::vector<std::string> y, names;
  std::vector<double> y_range;
  bool points = false;
};

std::vector<std::string_view> split_cells(std::string_view line) {
  std::vector<std::string_view> cells;
  for (std::size_t start = 0;;) {
    const std::size_t comma = line.find(',', start);
    std::string_view cell = line.substr(start, comma - start);
    while (!cell.empty() && (cell.front() == ' ' || cell.front() == '"')) cell.remove_prefix(1);
    while (!cell.empty() && (cell.back() == ' ' || cell.back() == '"' || cell.back() == '\r'))
      cell.remove_suffix(1);
    cells.push_back(cell);
    if (comma == std::string_view::npos) return cells;
    start = comma + 1;
  }
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

// The named columns of a CSV file; an empty cell is NaN (a gap in the line).
std::vector<std::vector<double>> read_columns(const std::string& path,
                                              const std::vector<std::string>& wanted) {
  io::LineReader reader(path);
  std::string_view line;
  if (!io::next_data_line(reader, line))
    throw io::InputError(path, 1, "a header line naming the columns (comma-separated)");
  std::vector<std::string> header;
  for (std::string_view cell : split_cells(line)) header.emplace_back(cell);
  std::vector<std::size_t> index;
  for (const std::string& name : wanted) {
    std::size_t k = 0;
    while (k < header.size() && header[k] != name) ++k;
    if (k == header.size())
      throw io::InputError(path, 1,
                           "a column named '" + name + "' (columns: " + joined(header) + ")");
    index.push_back(k);
  }
  std::vector<std::vector<double>> columns(wanted.size());
  while (io::next_data_line(reader, line)) {
    io::check_record_count(reader, columns[0].size(), "rows");
    const std::vector<std::string_view> cells = split_cells(line);
    if (cells.size() != header.size())
      throw io::InputError(
          path, reader.line_number(),
          std::to_string(header.size()) + " comma-separated cells like the header");
    for (std::size_t c = 0; c < index.size(); ++c) {
      const std::string_view cell = cells[index[c]];
      double v = std::nan("");
      if (!cell.empty() && (!io::parse_number(cell, v) || !std::isfinite(v)))
        throw io::InputError(path, reader.line_number(),
                             "a finite number or an empty cell in column '" + wanted[c] + "'");
      columns[c].push_back(v);
    }
  }
  if (columns[0].empty()) throw io::InputError(path, 2, "at least one data row after the header");
  return columns;
}

void run_plot(const PlotArgs& a) {
  std::vector<std::string> wanted = {a.x};
  wanted.insert(wanted.end(), a.y.begin(), a.y.end());
  const std::vector<std::vector<double>> columns = read_columns(a.csv, wanted);
  if (!a.names.empty() && a.names.size() != a.y.size())
    throw std::invalid_argument("--names: one legend name per --y column (" +
                                std::to_string(a.y.size()) + "), got " +
                                std::to_string(a.names.size()));
  std::vector<report::Series> series;
  for (std::size_t c = 1; c < columns.size(); ++c)
    series.push_back({a.names.empty() ? wanted[c] : a.names[c - 1], columns[0], columns[c], ""});
  report::PlotOptions options;
  options.title = a.title;
  options.x_label = a.x_label.empty() ? a.x : a.x_label;
  options.y_label = a.y_label;
  options.x_min = options.x_max = options.y_min = options.y_max = 0;  // ranged from the data
  if (a.y_range.size() == 2) {
    options.y_min = a.y_range[0];
    options.y_max = a.y_range[1];
  }
  options.points = a.points;
  io::write_file_atomic(a.out, report::line_plot_svg(series, options));
  std::printf("%zu series, %zu points each -> %s\n", series.size(), columns[0].size(),
              shown(a.out).c_str());
}

}  // namespace

void add_plot_command(CLI::App& app) {
  auto args = std::make_shared<PlotArgs>();
  CLI::App* cmd = app.add_subcommand(
      "plot", "Plot columns of a CSV file with a header (pr.csv, sweeps) as an SVG line plot");
  cmd->add_option("--csv", args->csv, "CSV file (or .gz) whose first line names the columns")
      ->required();
  cmd->add_option("--x", args->x, "column for the x axis")->required();
  cmd->add_option("--y", args->y, "one or more columns, one line each")->required();
  // Legend texts may contain commas: one name per argument (never split at a comma).
  cmd->add_option("--names", args->names, "legend names, one per --y column (default: the columns)")
      ->delimiter('\n');
  cmd->add_option("--out", args->out, "SVG file to write")->required();
  cmd->add_option("--title", args->title, "figure title");
  cmd->add_option("--x-label", args->x_label, "x axis label (default: the column name)");
  cmd->add_option("--y-label", args->y_label, "y axis label");
  cmd->add_option("--y-range", args->y_range, "LO HI: the y axis range (default: the data's)")
      ->expected(2)
      ->check(finite_in(-1e12, 1e12));
  cmd->add_flag("--points", args->points, "markers instead of lines");
  cmd->callback([args] {
    PlotArgs a = *args;
    with_output_file(
        a.out, [](const std::string& path) { return starts_with_bytes(path, "<?xml"); },
        [&] { run_plot(a); });
  });
}

}  // namespace loopscan::cli
