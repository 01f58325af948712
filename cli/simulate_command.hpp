#pragma once
/// \file simulate_command.hpp
/// \brief `nhc simulate`: its flags and the run they ask for (simulate_command.cpp).

#include <string>

#include "run_flags.hpp"
#include "sensitivity_option.hpp"

namespace nhc::cli {

struct SimulateOptions {
  RunFlags run;
  std::string columns;
  std::string output;
  std::string plot, plot_xy;  // trajectory_plots.hpp
  SensitivityRequest sensitivity;
};

/// The command's body: the scene of `options.run` prepared, checked and built through the
/// application layer (app::prepare_and_build), integrated, written and summarised; the exit code.
int run_simulate(SimulateOptions& options);

}  // namespace nhc::cli
