#pragma once
/// \file sensitivity_option.hpp
/// \brief `nhc simulate --sensitivity g,alpha,x'(0)`: the names as runtime::SensitivityParameter,
/// the run with IDAS, and its cost relative to the plain run (README, "simulate").

#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "nhc/runtime/runtime.hpp"

namespace nhc::cli {

struct SensitivityRequest {
  std::vector<std::string> names;  ///< empty: no sensitivities
  std::string error_control = "on";
};

/// Registers --sensitivity and --sensitivity-error-control on `sub`.
void add_sensitivity_options(CLI::App* sub, SensitivityRequest& request);

/// InputError naming --sensitivity for an initial value the scene does not give (the hidden
/// constraints fix it, so it cannot be varied on its own). The quantities themselves:
/// app::sensitivity_parameters.
void check_sensitivities_given(const std::vector<runtime::SensitivityParameter>& thetas,
                               const runtime::InitialState& initial);

/// One summary line: the sensitivities' cost against the plain run's statistics.
std::string describe_sensitivity_cost(const runtime::SensitivityRun& run, const SensitivityRequest& request,
                                      const runtime::Statistics& plain);

}  // namespace nhc::cli
