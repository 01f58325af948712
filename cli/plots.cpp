// Line plots of CSV columns with gnuplot (plots.hpp).
#include "plots.hpp"

#include "nhc/io/csv_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "nhc/errors.hpp"
#include "nhc/io/atomic_file.hpp"
#include "nhc/tools/gnuplot.hpp"
#include "nhc/base/number_text.hpp"

namespace nhc::cli {

namespace fs = std::filesystem;

int CsvTable::column(const std::string& name) const {
  const auto it = std::find(header.begin(), header.end(), name);
  return it == header.end() ? -1 : static_cast<int>(it - header.begin());
}

CsvTable read_csv_table(const fs::path& path, bool finite_only) {
  // The one CSV reader of data files (nhc/io/csv_file.hpp): its limits and messages.
  const CsvFile file = read_csv_file(path.string(), "a CSV file");
  CsvTable table;
  table.header = file.header;
  table.rows = file.numbers(finite_only);
  return table;
}

namespace {

/// Okabe & Ito's palette (distinguishable with colour-vision deficiencies), yellow left out.
constexpr const char* kColours[] = {"#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000"};
/// Markers that stay distinguishable when they lie on top of each other: open square, filled
/// circle, open triangle, filled diamond, open circle, filled triangle.
constexpr int kPointTypes[] = {4, 7, 8, 13, 6, 9};
constexpr int kWidth = 900, kHeight = 560;

std::string number(double v) { return base::shortest_text(v); }

/// The smallest and largest finite value seen.
struct Range {
  double low = INFINITY, high = -INFINITY;
  void add(double v) {
    if (std::isfinite(v)) low = std::min(low, v), high = std::max(high, v);
  }
  bool empty() const { return !(low <= high); }
  /// Too narrow for gnuplot's autoscaling (it warns on an empty range, and tics of a range
  /// narrower than rounding are unreadable).
  bool degenerate() const {
    return !empty() && high - low <= 1e-12 * std::max({std::abs(low), std::abs(high), 1e-300});
  }
  double span() const { return high - low; }
};

double transformed(double v, Transform transform, double first) {
  switch (transform) {
    case Transform::value:
      return v;
    case Transform::magnitude:
      return std::isnan(v) ? v : std::max(std::abs(v), kLogFloor);
    case Transform::drift:
      return std::isnan(v) ? v : std::max(std::abs(v - first), kLogFloor);
  }
  return v;
}

/// A curve's columns in its CSV file, and the first value of y (the drift's origin).
struct ResolvedCurve {
  int x = 0, y = 0;  // 0-based
  double first = 0;
  std::size_t rows = 0;
};

/// The `using` expression drawing the transform of column y (1-based in gnuplot).
std::string using_clause(const Curve& curve, const ResolvedCurve& r) {
  const std::string x = std::to_string(r.x + 1), y = "column(" + std::to_string(r.y + 1) + ")";
  const std::string floor = number(kLogFloor);
  switch (curve.transform) {
    case Transform::value:
      return x + ":" + std::to_string(r.y + 1);
    case Transform::magnitude:
      return x + ":(v = abs(" + y + "), v != v ? NaN : (v > " + floor + " ? v : " + floor + "))";
    case Transform::drift:
      return x + ":(v = abs(" + y + " - (" + number(r.first) + ")), v != v ? NaN : (v > " + floor + " ? v : " + floor +
             "))";
  }
  return x + ":" + y;
}

/// The range statement for a degenerate axis: a band around its value.
std::string fixed_range(const std::string& axis, const Range& range, bool log) {
  const double v = range.high;
  if (log) return "set " + axis + "range [" + number(v / 10) + ":" + number(v * 10) + "]\n";
  const double half = v != 0 ? 0.1 * std::abs(v) : 1.0;
  return "set " + axis + "range [" + number(v - half) + ":" + number(v + half) + "]\n";
}

std::string plot_script(const fs::path& dir, const Plot& plot) {
  std::vector<ResolvedCurve> resolved;
  Range xs, ys;
  for (const Curve& c : plot.curves) {
    const CsvTable table = read_csv_table(dir / c.csv);
    ResolvedCurve r{table.column(c.x), table.column(c.y), 0, table.rows.size()};
    if (r.x < 0 || r.y < 0)
      throw std::logic_error(c.csv + " has no column " + (r.x < 0 ? c.x : c.y) + " (plot " + plot.stem + ")");
    if (table.rows.empty()) throw std::logic_error(c.csv + " has no rows to plot (plot " + plot.stem + ")");
    r.first = table.rows.front()[r.y];
    for (const auto& row : table.rows) {
      xs.add(row[r.x]);
      ys.add(transformed(row[r.y], c.transform, r.first));
    }
    resolved.push_back(r);
  }
  if (xs.empty() || ys.empty()) throw std::logic_error("plot " + plot.stem + ": no finite values");

  std::ostringstream g;
  g << tools::gnuplot_comment(plot.title)
    << tools::gnuplot_comment("drawn by nhc from the CSV files beside it; redraw with: gnuplot " + plot.stem + ".gp")
    << "reset\n"  // gnuplot runs the scripts one after another: no setting carries over
    << "set datafile separator ','\n"
    << "set terminal svg size " << kWidth << "," << kHeight
    << " dynamic enhanced font 'sans,13' background rgb 'white'\n"
    << "set output " << tools::gnuplot_string(plot.stem + ".svg") << "\n"
    << "set title " << tools::gnuplot_string(plot.title) << " noenhanced\n"
    << "set xlabel " << tools::gnuplot_string(plot.xlabel) << " noenhanced\n"
    << "set ylabel " << tools::gnuplot_string(plot.ylabel) << " noenhanced\n"
    << "set grid\nset key outside right top\nset border lw 1.2\n";
  for (std::size_t k = 0; k < std::size(kColours); ++k)
    g << "set linetype " << k + 1 << " lc rgb '" << kColours[k] << "'\n";
  g << "set linetype cycle " << std::size(kColours) << "\n";
  if (plot.log_y) g << "set logscale y\nset format y '10^{%L}'\n";
  if (xs.degenerate()) g << fixed_range("x", xs, false);
  if (ys.degenerate()) g << fixed_range("y", ys, plot.log_y);
  // Equal scales only when both axes span something and neither dwarfs the other.
  if (plot.equal_scales && !xs.degenerate() && !ys.degenerate() && xs.span() < 10 * ys.span() &&
      ys.span() < 10 * xs.span())
    g << "set size ratio -1\n";
  g << "plot ";
  const std::size_t n = plot.curves.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Curve& c = plot.curves[i];
    // Earlier curves drawn wider, and markers of different shapes at every tenth or so point:
    // curves that coincide stay visible as stripes under each other.
    const double width = 1.5 + 1.5 * static_cast<double>(n - 1 - i);
    const std::size_t interval = std::max<std::size_t>(1, resolved[i].rows / 10);
    g << (i ? ", \\\n     " : "") << tools::gnuplot_string(c.csv) << " skip 1 using " << using_clause(c, resolved[i])
      << " with linespoints lt " << i + 1 << " lw " << width << " pt " << kPointTypes[i % std::size(kPointTypes)]
      << " ps 1.3 pi " << interval << " title " << tools::gnuplot_string(c.title) << " noenhanced";
  }
  g << "\n"
    << "if (strstrt(GPVAL_TERMINALS, 'pngcairo') > 0) {\n"
    << "  set terminal pngcairo size " << kWidth << "," << kHeight
    << " enhanced font 'sans,12' background rgb 'white'\n"
    << "} else {\n"
    << "  set terminal png size " << kWidth << "," << kHeight << " enhanced background rgb 'white'\n"
    << "}\n"
    << "set output " << tools::gnuplot_string(plot.stem + ".png") << "\n"
    << "replot\nset output\n";
  return g.str();
}

}  // namespace

void require_gnuplot(const std::string& flag) {
  if (const auto missing = tools::gnuplot_missing())
    throw InputError({flag, 0, 0}, *missing + ", so no plots can be drawn");
}

void draw_plots(const fs::path& dir, const std::vector<Plot>& plots) {
  if (plots.empty()) return;
  std::vector<std::string> scripts;
  for (const Plot& plot : plots) {
    const std::string script = plot_script(dir, plot);
    write_file_atomically((dir / (plot.stem + ".gp")).string(), [&](std::ostream& out) { out << script; });
    scripts.push_back(plot.stem + ".gp");
  }
  std::string messages;
  const int status = tools::run_gnuplot(dir, scripts, messages);
  // gnuplot prints nothing on success: every line is a warning or an error.
  if (status != 0 || !messages.empty())
    throw std::runtime_error("gnuplot " + std::string(status != 0 ? "failed" : "warned") + " in " + dir.string() +
                             ":\n" + messages);
  for (const Plot& plot : plots)
    for (const char* ext : {".svg", ".png"})
      if (!fs::exists(dir / (plot.stem + ext)))
        throw std::runtime_error("gnuplot wrote no " + (dir / (plot.stem + ext)).string());
}

std::string markdown_images(const std::vector<Plot>& plots, const std::string& prefix) {
  std::ostringstream md;
  for (const Plot& plot : plots) md << "![" << plot.title << "](" << prefix << plot.stem << ".svg)\n\n";
  return md.str();
}

}  // namespace nhc::cli
