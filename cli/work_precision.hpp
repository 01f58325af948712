#pragma once
/// \file work_precision.hpp
/// \brief Work-precision measurements for `nhc report`: one model of a scene integrated at a
/// series of tolerances, in several solver configurations (dense LU or KLU, with or without
/// projection onto the hidden constraints), optionally over a sweep of one parameter, with the
/// error of every run (against the scene's [reference], else against a reference run at a tight
/// tolerance), its wall time (median of repeats for short runs), drift and solver statistics.
/// Also the CSV file and the gnuplot plots of the measurements.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::cli {

/// One solver configuration of a series.
struct Configuration {
  std::string jacobian;  ///< "dense" or "sparse"
  bool projection = false;
  std::string label() const;  ///< "dense", "sparse + projection"
};

struct WorkPrecisionSettings {
  std::vector<double> rtols;      ///< loosest first
  double atol_scale = 1e-2;       ///< atol = rtol × atol_scale
  double t_end = 1;
  int outputs = 200;              ///< error and drift are measured at outputs + 1 equally spaced times
  double reference_rtol = 1e-13;  ///< the reference run when the scene has no [reference]
  int max_repeats = 5;            ///< repeat a run while the total time is below repeat_seconds
  double repeat_seconds = 0.2;
  std::vector<Configuration> configurations;
  std::string sweep_parameter;     ///< empty: no sweep
  std::vector<double> sweep_values;
  std::vector<std::pair<std::string, double>> parameter_overrides;
};

/// One run.
struct Measurement {
  Configuration configuration;
  std::optional<double> sweep_value;
  double rtol = 0, atol = 0;
  double error = 0;     ///< max over output times and coordinates of |q − q_ref|; NaN when nothing to compare
  double seconds = 0;   ///< wall time of runtime::simulate (initialization + integration), median of repeats
  int repeats = 1;
  runtime::Statistics statistics;
  double max_hidden = 0;              ///< max |g_i| over the outputs
  double max_invariant_relative = 0;  ///< max over invariants of max |I(t) − I(t0)| / |I(t0)|
  double t_reached = 0;
  std::optional<runtime::FailureKind> failure;
  double failure_t = 0;
  std::string failure_message;
  std::string status() const;  ///< "ok" or the failure kind with underscores
};

/// The reference a series was measured against.
struct ErrorSource {
  bool exact = false;  ///< the scene's [reference]; else a reference run
  double rtol = 0, atol = 0;  ///< of the reference run
  std::string description() const;
};

struct WorkPrecision {
  std::string scene_name, model_name;
  int n_states = 0, n_hidden = 0, n_invariants = 0;
  std::vector<std::string> state_names, hidden_names, invariant_names, singular_names;
  std::vector<std::string> parameter_names;
  std::vector<double> parameters;  ///< after overrides, before the sweep
  WorkPrecisionSettings settings;
  ErrorSource source;
  std::vector<Measurement> measurements;
  double derive_seconds = 0, compile_seconds = 0;
};

/// Progress callback: one line of text per finished run.
using ProgressSink = std::function<void(const std::string&)>;

/// Builds the scene's model in every needed Jacobian flavour and runs the series.
/// Throws InputError for an unknown parameter, MathError when the model does not apply.
WorkPrecision measure_work_precision(const Scene& scene, ModelKind kind, const WorkPrecisionSettings& settings,
                                     const ProgressSink& progress);

/// rtol values by decades from `spec` = "HI:LO" (e.g. "1e-3:1e-12") or a single value.
/// Throws std::invalid_argument with a message for a malformed spec.
std::vector<double> decades(const std::string& spec);

/// CSV: configuration, jacobian, projection, parameter, value, rtol, atol, error, error_source,
/// seconds, repeats, steps, residual_evaluations, jacobian_evaluations, linear_solver_setups,
/// error_test_failures, nonlinear_iterations, nonlinear_failures, projections, max_hidden_drift,
/// max_invariant_drift, t_end, t_reached, status. Written atomically.
void write_work_precision_csv(const std::string& path, const WorkPrecision& wp);

/// Draws `DIR/workprec.svg` and `.png` (log-log error against seconds, one curve per
/// configuration and sweep value) and, for a sweep, `DIR/steps.svg` and `.png` (steps against the
/// parameter, one curve per configuration and tolerance) with gnuplot; the data and the gnuplot
/// script stay in DIR. Each image is written to a temporary file and renamed. Throws
/// std::runtime_error when gnuplot is missing or fails. Returns the images written.
std::vector<std::string> plot_work_precision(const std::string& directory, const WorkPrecision& wp);

}  // namespace nhc::cli
