#pragma once
/// \file plot.hpp
/// \brief Maps of an ensemble's outcome: a heat map over a 2-D grid, a line over a 1-D grid,
/// points for random samples of one or two variables (gnuplot, SVG and PNG).

#include <string>
#include <vector>

#include "nhc/ensemble/results_file.hpp"

namespace nhc::ensemble {

/// An outcome per run: `t_stop`, `steps`, `seconds`, `final:<state>` (e.g. `final:x'`),
/// `drift:<invariant>`, `drift:hidden`. NaN for runs that have none (pending; failed, except
/// t_stop). Throws InputError (flag `flag`) naming the outcomes that exist.
std::vector<double> outcome_values(const EnsembleResults& results, const std::string& outcome, const std::string& flag);

/// The outcomes `results` offers, for messages and --help.
std::vector<std::string> outcome_names(const EnsembleInfo& info);

/// `<stem>.svg` and `<stem>.png` of `outcome` (written atomically), and `<stem>.dat` and
/// `<stem>.gp` to redraw them by hand. Returns the images written. Throws InputError when the
/// design has more than two variables or an output is one of `inputs` (the files of the run,
/// nhc/io/output_path.hpp), std::runtime_error when gnuplot fails.
std::vector<std::string> plot_outcome(const EnsembleResults& results, const std::string& outcome,
                                      const std::string& stem, const std::string& flag,
                                      const std::vector<std::string>& inputs);

/// `FILE.h5` → `FILE_<outcome>` with characters other than letters, digits and _ replaced.
std::string default_plot_stem(const std::string& h5_path, const std::string& outcome);

}  // namespace nhc::ensemble
