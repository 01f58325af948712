#pragma once
/// \file work_precision.hpp
/// \brief Work-precision for `nhc report`: builds a scene's model in the Jacobian flavours the
/// configurations need, runs the library's measurement (nhc/runtime/work_precision.hpp), and
/// writes the CSV file and the gnuplot plots of the results.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "nhc/runtime/runtime.hpp"
#include "nhc/runtime/work_precision.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::cli {

// The measurement is the runtime's (nhc/runtime/work_precision.hpp); the command adds the
// build times and writes the results.
using Configuration = runtime::WorkPrecisionConfiguration;
using WorkPrecisionSettings = runtime::WorkPrecisionSettings;
using Measurement = runtime::WorkPrecisionMeasurement;
using ErrorSource = runtime::ErrorSource;
using ProgressSink = runtime::ProgressSink;

/// The measurement and what building the models took.
struct WorkPrecision : runtime::WorkPrecision {
  double derive_seconds = 0, compile_seconds = 0;
};

/// Builds the scene's model in every needed Jacobian flavour and runs the series.
/// Throws InputError for an unknown parameter, MathError when the model does not apply.
WorkPrecision measure_work_precision(const Scene& scene, ModelKind kind, const WorkPrecisionSettings& settings,
                                     const ProgressSink& progress);

/// rtol values by decades from `spec` = "HI:LO" (e.g. "1e-3:1e-12") or a single value.
/// Throws std::invalid_argument with a message for a malformed spec.
std::vector<double> decades(const std::string& flag, const std::string& spec);

/// CSV: configuration, jacobian, projection, parameter, value, rtol, atol, step (variational),
/// error, error_source,
/// seconds, repeats, steps, residual_evaluations, jacobian_evaluations, linear_solver_setups,
/// error_test_failures, nonlinear_iterations, nonlinear_failures, projections, max_hidden_drift,
/// max_invariant_drift, t_end, t_reached, status. Written atomically.
void write_work_precision_csv(const std::string& path, const WorkPrecision& wp);

/// Draws `DIR/workprec.svg` and `.png` (log-log error against seconds, one curve per
/// configuration and sweep value), for a long run `DIR/energy.svg` and `.png` (the energy error
/// against t of both integrators) and, for a sweep, `DIR/steps.svg` and `.png` (steps against the
/// parameter, one curve per configuration and tolerance) with gnuplot; the data and the gnuplot
/// script stay in DIR. Each image is written to a temporary file and renamed. Throws
/// std::runtime_error when gnuplot is missing or fails. Returns the images written.
std::vector<std::string> plot_work_precision(const std::string& directory, const WorkPrecision& wp);

}  // namespace nhc::cli
