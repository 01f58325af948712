#pragma once
/// \file plots.hpp
/// \brief Line plots of CSV columns drawn by gnuplot (Debian gnuplot-nox) as SVG and PNG, for
/// any command that writes CSV files into an output directory (nhc simulate --plot, nhc compare).
///
/// Each plot becomes `stem.gp` (the gnuplot script, kept so that the picture can be redrawn or
/// restyled by hand: `cd DIR && gnuplot stem.gp`), `stem.svg` and `stem.png`. The scripts read
/// the CSV files themselves, so the numbers in the pictures are the numbers in the CSV files.

#include <filesystem>
#include <string>
#include <vector>

namespace nhc::cli {

/// A CSV file of numbers with a header line, as nhc writes them (runtime::write_csv).
struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;

  /// Index of the column named `name`, -1 when there is none.
  int column(const std::string& name) const;
};

/// Reads a CSV file written by nhc ("nan", "inf" read as such) with the data-file rules of
/// read_csv_file (nhc/io/csv_file.hpp). Throws InputError at the file, line and column.
/// `finite_only`: nan and ±inf refused too (a motion read back to draw: `nhc animate --path`).
CsvTable read_csv_table(const std::filesystem::path& path, bool finite_only = false);

/// What of a column is drawn.
enum class Transform {
  value,      ///< the value
  magnitude,  ///< |value|, on a log axis (a hidden-constraint residual)
  drift,      ///< |value − value in the first row|, on a log axis (an invariant)
};

/// Log axes have no zero: magnitudes below this are drawn at it.
inline constexpr double kLogFloor = 1e-17;

/// One curve: column `y` against column `x` of a CSV file in the plot directory.
struct Curve {
  std::string title;  ///< the legend entry, printed as is (no gnuplot markup)
  std::string csv;    ///< file name, relative to the plot directory
  std::string x, y;   ///< column names
  Transform transform = Transform::value;
};

struct Plot {
  std::string stem;  ///< file name stem: stem.gp, stem.svg, stem.png
  std::string title, xlabel, ylabel;
  bool log_y = false;
  bool equal_scales = false;  ///< one unit is as long on both axes (a path in a plane), when sensible
  std::vector<Curve> curves;
};

/// InputError naming `flag` when gnuplot cannot be run (checked before any work is done).
void require_gnuplot(const std::string& flag);

/// Writes the script of each plot into `dir`, where the CSV files are, and runs gnuplot on them
/// there. Throws std::runtime_error with gnuplot's messages when it fails or prints anything:
/// a warning (an empty range, a file without valid points) is treated as a failure.
void draw_plots(const std::filesystem::path& dir, const std::vector<Plot>& plots);

/// Markdown showing the SVG of each plot, its title as the alternative text (plots.md, compare.md).
std::string markdown_images(const std::vector<Plot>& plots, const std::string& prefix = "");

}  // namespace nhc::cli
