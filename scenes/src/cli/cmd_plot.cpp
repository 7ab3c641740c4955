// `grainflow plot FILE.csv… --x COL --y COL…`: line plots of a run's stats.csv (or any
// numeric CSV with a header) drawn by render/plot — several --y columns, one --y-err per
// --y, log axes, a title and axis labels. The same pixels every time. --rows joins files
// into one table (a sweep's study.csv files) and --group splits it into series.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "engine/core/error.hpp"
#include "engine/io/line_reader.hpp"
#include "render/context/gl_context.hpp"
#include "render/output/png_io.hpp"
#include "render/plot/plot.hpp"
#include "scenes/src/cli/commands.hpp"
#include "scenes/src/scene/suggest.hpp"

namespace grainflow::scenes {

namespace {

namespace fs = std::filesystem;

struct PlotArgs {
  std::vector<std::string> files, y, y_err;
  std::string x = "time", out, title, x_label, y_label, backend = "auto", group;
  bool log_x = false, log_y = false, points = false, force = false, rows = false;
  std::vector<int> size = {800, 560};
};

// A numeric CSV: a header of names, then rows of numbers ("nan", "inf" allowed; an
// empty cell is NaN). values[column][row].
struct CsvTable {
  std::string path;
  std::vector<std::string> columns;
  std::vector<std::vector<double>> values;

  std::size_t column(const std::string& name) const {
    for (std::size_t i = 0; i < columns.size(); ++i)
      if (columns[i] == name) return i;
    std::string list;
    for (const auto& c : columns) list += (list.empty() ? "" : ", ") + c;
    const auto near = closest_match(name, columns);
    throw Error(path + ": no column '" + io::printable(name) + "'" + (near ? "; did you mean '" + *near + "'?" : "") +
                " (columns: " + list + ")");
  }
};

void split_commas(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = line.find(',', start);
    out.push_back(io::trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) return;
    start = comma + 1;
  }
}

CsvTable read_csv(const std::string& path) {
  if (fs::is_directory(path))
    throw Error(path + " is a folder; allowed: a CSV file (a run's stats.csv: " + (fs::path(path) / "stats.csv").string() +
                ")");
  io::LineReader in(path);
  CsvTable t;
  t.path = path;
  std::string_view line;
  std::vector<std::string_view> cells;
  if (!in.next(line)) throw Error(path + " is empty; allowed: a header line of column names, then rows of numbers");
  split_commas(line, cells);
  for (auto c : cells) {
    if (c.empty()) in.fail("an empty column name in the header");
    for (const auto& seen : t.columns)
      if (seen == c) in.fail("the column '" + io::printable(c) + "' appears twice in the header");
    t.columns.emplace_back(c);
  }
  t.values.resize(t.columns.size());
  while (in.next(line)) {
    if (io::trim(line).empty()) continue;
    split_commas(line, cells);
    if (cells.size() != t.columns.size())
      in.fail(std::to_string(cells.size()) + " cells, the header has " + std::to_string(t.columns.size()));
    for (std::size_t i = 0; i < cells.size(); ++i) {
      double v = std::nan("");
      if (!cells[i].empty() && !io::parse_double(cells[i], v))
        in.fail("'" + io::printable(cells[i]) + "' in column '" + t.columns[i] + "' is not a number");
      t.values[i].push_back(v);
    }
  }
  if (t.values.empty() || t.values[0].empty()) throw Error(path + " has a header but no rows: nothing to plot");
  return t;
}

// A series' name in the legend: the column, with the run's folder when several files
// are drawn (out/a/stats.csv → "a: kT").
std::string file_label(const std::string& path) {
  const fs::path p(path);
  return (p.filename() == "stats.csv" || p.filename() == "study.csv") && p.has_parent_path() ? p.parent_path().filename().string() : p.stem().string();
}

int run_plot(const PlotArgs& a) {
  if (a.y.empty()) throw Error("plot: no --y column given; allowed: one or more --y COLUMN");
  if (!a.y_err.empty() && a.y_err.size() != a.y.size())
    throw Error("plot: " + std::to_string(a.y_err.size()) + " --y-err for " + std::to_string(a.y.size()) +
                " --y; allowed: none, or one per --y in the same order ('-' for none)");
  if (fs::exists(a.out) && !a.force)
    throw Error("plot: " + a.out + " exists; allowed: another -o, or --force to replace it");
  render::plot::Figure f;
  f.width = a.size[0];
  f.height = a.size[1];
  f.title = a.title;
  f.x.log = a.log_x;
  f.y.log = a.log_y;
  f.x.label = a.x_label.empty() ? a.x : a.x_label;
  if (!a.y_label.empty()) f.y.label = a.y_label;
  else if (a.y.size() == 1) f.y.label = a.y[0];
  // --rows: the files are the rows of one table (a sweep's study.csv files, one run each).
  std::vector<CsvTable> tables;
  for (const auto& file : a.files) {
    CsvTable t = read_csv(file);
    if (a.rows && !tables.empty()) {
      if (t.columns != tables[0].columns)
        throw Error("plot --rows: " + file + " has other columns than " + tables[0].path +
                    "; allowed: files of one kind (the study.csv of runs of one study)");
      for (std::size_t c = 0; c < t.columns.size(); ++c)
        tables[0].values[c].insert(tables[0].values[c].end(), t.values[c].begin(), t.values[c].end());
      continue;
    }
    tables.push_back(std::move(t));
  }
  if (a.rows) tables[0].path = std::to_string(a.files.size()) + " files (" + a.files[0] + ", …)";
  // --group COL: one series per distinct value of COL (r = 0.97, r = 0.87), rows sorted by x.
  std::vector<CsvTable> split;
  if (!a.group.empty()) {
    for (const CsvTable& t : tables) {
      const auto& g = t.values[t.column(a.group)];
      const auto& xs = t.values[t.column(a.x)];
      std::vector<double> keys;
      for (double v : g)
        if (std::find(keys.begin(), keys.end(), v) == keys.end()) keys.push_back(v);
      std::sort(keys.begin(), keys.end());
      for (double key : keys) {
        CsvTable part;
        char label[64];
        std::snprintf(label, sizeof label, "%s = %g", a.group.c_str(), key);
        part.path = label;
        part.columns = t.columns;
        part.values.resize(t.columns.size());
        std::vector<std::size_t> order;
        for (std::size_t i = 0; i < g.size(); ++i)
          if (g[i] == key) order.push_back(i);
        std::stable_sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return xs[i] < xs[j]; });
        for (std::size_t c = 0; c < t.columns.size(); ++c)
          for (std::size_t i : order) part.values[c].push_back(t.values[c][i]);
        split.push_back(std::move(part));
      }
    }
    tables = std::move(split);
  } else if (a.rows) {
    // A sweep's rows in the order of x, so that the line joins neighbours.
    CsvTable& t = tables[0];
    const auto& xs = t.values[t.column(a.x)];
    std::vector<std::size_t> order(xs.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) { return xs[i] < xs[j]; });
    for (auto& col : t.values) {
      std::vector<double> sorted;
      for (std::size_t i : order) sorted.push_back(col[i]);
      col = std::move(sorted);
    }
  }
  for (const CsvTable& t : tables) {
    const std::string& file = t.path;
    const auto& x = t.values[t.column(a.x)];
    for (std::size_t k = 0; k < a.y.size(); ++k) {
      render::plot::Series s;
      s.x = x;
      s.y = t.values[t.column(a.y[k])];
      if (!a.y_err.empty() && a.y_err[k] != "-") s.y_err = t.values[t.column(a.y_err[k])];
      // A NaN error is "no bar"; a negative one is a wrong column.
      for (std::size_t i = 0; i < s.y_err.size(); ++i)
        if (s.y_err[i] < 0)
          throw Error(file + ": row " + std::to_string(i + 1) + " of the error column '" + a.y_err[k] + "' is " +
                      std::to_string(s.y_err[i]) + "; allowed: error bars ≥ 0");
      s.style = a.points ? render::plot::SeriesStyle::line_points : render::plot::SeriesStyle::line;
      const bool many = tables.size() > 1, many_y = a.y.size() > 1;
      const std::string name = a.group.empty() ? file_label(file) : file;
      s.label = many ? name + (many_y ? ": " + a.y[k] : "") : many_y ? a.y[k] : "";
      f.series.push_back(std::move(s));
    }
    // Which file a log-axis complaint is about.
    try {
      render::plot::axis_range(f, true);
      render::plot::axis_range(f, false);
    } catch (const Error& e) {
      throw Error(file + ": " + e.what());
    }
  }
  std::string notice;
  auto ctx = render::create_context(render::parse_backend(a.backend), &notice);
  if (!notice.empty()) std::fprintf(stderr, "grainflow: %s\n", notice.c_str());
  render::write_png(a.out, render::plot::draw_figure(*ctx, f), {6, true});
  std::printf("plot: %s (%zu series, %d × %d)\n", a.out.c_str(), f.series.size(), f.width, f.height);
  return 0;
}

}  // namespace

void setup_plot_command(CLI::App& app, int& status) {
  auto* cmd = app.add_subcommand("plot", "Draw columns of CSV files (a run's stats.csv) as a line plot PNG");
  auto args = std::make_shared<PlotArgs>();
  cmd->add_option("FILES", args->files, "CSV files with a header line (stats.csv); several draw one series each")
      ->required()
      ->check(CLI::ExistingPath);
  cmd->add_option("--x", args->x, "Column on the x axis")->capture_default_str();
  cmd->add_option("--y", args->y, "Column(s) on the y axis (repeat for several series)")->required();
  cmd->add_option("--y-err", args->y_err, "Error-bar half-width column, one per --y in order ('-' for none)");
  cmd->add_flag("--log-x", args->log_x, "Logarithmic x axis (every value must be positive)");
  cmd->add_flag("--log-y", args->log_y, "Logarithmic y axis (every value must be positive)");
  cmd->add_flag("--points", args->points, "Mark every point (default: lines only)");
  cmd->add_flag("--rows", args->rows,
                "The files are the rows of one table (a sweep: each run's study.csv), drawn in the order of --x");
  cmd->add_option("--group", args->group, "One series per distinct value of this column (e.g. r)");
  cmd->add_option("--title", args->title, "Title above the plot");
  cmd->add_option("--xlabel", args->x_label, "x axis label (default: the --x column)");
  cmd->add_option("--ylabel", args->y_label, "y axis label (default: the --y column when there is one)");
  cmd->add_option("--size", args->size, "Width and height in pixels")->expected(2)->capture_default_str();
  cmd->add_option("-o,--out", args->out, "The PNG to write")->required();
  cmd->add_flag("--force", args->force, "Replace the PNG if it exists");
  cmd->add_option("--backend", args->backend, "Off-screen GL backend: auto|egl|osmesa")->capture_default_str();
  cmd->callback([args, &status] { status = run_plot(*args); });
}

}  // namespace grainflow::scenes
