#pragma once
/// \file compare_report.hpp
/// \brief DIR/compare.md of `nhc compare`: the models' outcomes, their consistent initial points,
/// per pair of models the largest difference of each coordinate and the time the motions
/// separate, the invariants and hidden constraints per model, the plots. Every number is read
/// back from the models' CSV files in DIR, so the report says what the files hold.

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "plots.hpp"

namespace nhc::cli {

/// A constraint f^α of the scene evaluated along a model's motion.
struct ConstraintCheck {
  std::string name;    ///< "f1: z' - b/a*sqrt(x'^2 + y'^2)"
  double at_t0 = 0;    ///< f^α at t0 (NaN: not computable from the CSV columns)
  double largest = 0;  ///< max_t |f^α|
};

/// One model as `nhc compare` ran it.
struct ComparedModel {
  std::string name;         ///< "chetaev"
  std::string csv;          ///< its CSV file in DIR; empty when it did not run
  std::string outcome;      ///< "ran to the end", "stopped at a singularity at t = …: …"
  std::string unavailable;  ///< why it does not apply, or stops at t0 (then csv is empty)
  std::vector<ConstraintCheck> constraints;
  long steps = 0;
  double build_seconds = 0, integrate_seconds = 0;
};

struct CompareSettings {
  std::string command_line;  ///< the command as given, for the reader to repeat it
  std::string scene_path, scene_name;
  std::vector<std::string> coordinates;
  std::map<std::string, std::vector<double>> given;  ///< the scene's [initial] values
  double t0 = 0, t_end = 0, rtol = 0, atol = 0;
  int outputs = 0;
  std::vector<double> times;  ///< the outputs + 1 output times, checked not to collapse
  double tolerance = 0;       ///< motions separate where a coordinate differs by more than this
};

/// Largest difference of two motions, on the output times both reached.
struct PairDifference {
  std::vector<double> max_difference;  ///< per coordinate, max_t |q_a − q_b|
  double separation = -1;              ///< first output time with some |q_a − q_b| > tolerance; −1: none
  double compared_until = 0;           ///< the last common output time
};

/// Compares the coordinates of two CSV files (nhc's trajectory format) row by row while their
/// times agree.
PairDifference compare_motions(const CsvTable& a, const CsvTable& b, const std::vector<std::string>& coordinates,
                               double tolerance);

/// The Markdown of compare.md. The wall times are the last section, "## Wall times", so that a
/// staleness check can leave them out.
std::string compare_markdown(const std::filesystem::path& dir, const CompareSettings& settings,
                             const std::vector<ComparedModel>& models, const std::vector<Plot>& plots);

}  // namespace nhc::cli
