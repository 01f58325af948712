#pragma once
/// \file optimize_options.hpp
/// \brief An `nhc optimize` request as the solver's options (nhc/optimize/solve.hpp, refine.hpp),
/// written once for the command line and Python. Header-only: only the programs that link the
/// optimizer (nhc-optimize, the Python module) include it, so the application library itself does
/// not link IPOPT.

#include "nhc/app/optimize_request.hpp"
#include "nhc/optimize/refine.hpp"
#include "nhc/optimize/solve.hpp"

namespace nhc::app {

/// IPOPT's options of a checked request; the caller adds its progress callback.
inline optimize::SolveOptions solve_options(const OptimizeRequest& request) {
  const OptimizeChoices choices = optimize_choices(request);
  optimize::SolveOptions options;
  options.max_iterations = choices.max_iterations;
  options.tolerance = choices.tolerance;
  options.finite_difference_jacobian = choices.jacobian == JacobianChoice::finite_differences;
  options.exact_hessian = choices.hessian == HessianChoice::exact;
  return options;
}

/// The mesh refinement's options of a checked request, from `intervals` (the request's, else the
/// scene's); the caller adds its report callback.
inline optimize::RefineOptions refine_options(const OptimizeRequest& request, int intervals) {
  optimize::RefineOptions options;
  options.intervals = intervals;
  options.path_tolerance = optimize_choices(request).path_tolerance;
  return options;
}

}  // namespace nhc::app
