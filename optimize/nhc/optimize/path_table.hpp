#pragma once
/// \file path_table.hpp
/// \brief The transcribed path as a table and back: the columns `nhc optimize` writes (t; each
/// state, and its rate where the rate is no state itself; each input) and the starting point
/// read from such a table or from `nhc simulate`'s CSV (`--guess`). Shared by the command and
/// the Python module.

#include <string>
#include <vector>

#include "nhc/optimize/hermite_simpson.hpp"

namespace nhc::optimize {

/// "t", then per state its name and its rate's ("x", "x'"; a rate that is itself a state, or an
/// algebraic state's, is left out), then the inputs: without [inputs] t,x,x',y,y',…
std::vector<std::string> path_columns(const HermiteSimpson& problem);
/// One row per collocation point, in path_columns() order.
std::vector<std::vector<double>> path_rows(const HermiteSimpson& problem, const std::vector<double>& z);

/// The starting point from a table with a header: column t (increasing), the scene's
/// coordinates (required), the other states, rates and inputs (NAME or simulate's input:NAME)
/// where present. InputError at
/// `where` ("--guess", "guess") naming `file` for a missing column or a t that does not increase.
std::vector<double> guess_from_table(const HermiteSimpson& problem, const std::vector<std::string>& header,
                                     const std::vector<std::vector<double>>& rows, const Scene& scene,
                                     const std::string& where, const std::string& file);

}  // namespace nhc::optimize
