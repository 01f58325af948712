#pragma once
/// \file work_precision.hpp
/// \brief Work-precision measurement of a loaded model: integrated at a series of tolerances in
/// several solver configurations (dense LU or KLU, with or without projection onto the hidden
/// constraints), optionally over a sweep of one parameter, with the error of every run (against
/// the model's reference solution, else against a reference run at a tight tolerance), its wall
/// time (median of repeats for short runs), drift and IDA's statistics. Returns data only; the
/// nhc command writes it as CSV, Markdown and plots (`nhc report`).

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "nhc/base/errors.hpp"
#include "nhc/runtime/integrator.hpp"
#include "nhc/runtime/model.hpp"
#include "nhc/runtime/trajectory.hpp"

namespace nhc::runtime {

/// One solver configuration of a series.
struct WorkPrecisionConfiguration {
  std::string jacobian;  ///< "dense" (dense LU) or "sparse" (KLU)
  bool projection = false;
  /// The variational integrator (variational.hpp) at the settings' steps instead of IDA at its
  /// tolerances.
  bool variational = false;
  std::string label() const;  ///< "dense", "sparse + projection", "variational"
};

/// One IDA run of a measurement: its rows (at the output times, and where it ended), statistics
/// and failure, and the rows its drift is measured over (those where the model's constraints
/// hold: a sliding contact's rows are not).
struct WorkPrecisionRun {
  RunResult run;
  std::vector<Sample> drift_samples;
};

/// Makes one IDA run of `model` (a Jacobian flavour of the measured model) with parameters `p`
/// from `initial`, its rows at `times`, with `options`: what a front end's run engine does (the
/// scene's events and contacts). Empty: runtime::simulate, the drift over every row.
using WorkPrecisionRunner =
    std::function<WorkPrecisionRun(const Model& model, const std::vector<double>& p, const InitialState& initial,
                                   const std::vector<double>& times, const IntegratorOptions& options)>;

struct WorkPrecisionSettings {
  std::vector<double> rtols;  ///< loosest first
  double atol_scale = 1e-2;   ///< atol = rtol × atol_scale
  double t_end = 1;
  int outputs = 200;              ///< error and drift are measured at outputs + 1 equally spaced times
  double reference_rtol = 1e-13;  ///< the reference run when the model has no reference solution
  int max_repeats = 5;            ///< repeat a run while the total time is below repeat_seconds
  double repeat_seconds = 0.2;
  std::vector<WorkPrecisionConfiguration> configurations;
  std::string sweep_parameter;  ///< empty: no sweep
  std::vector<double> sweep_values;
  std::vector<std::pair<std::string, double>> parameter_overrides;
  /// The fixed steps of a variational configuration, largest first.
  std::vector<double> steps;
  /// > t0: also a long run of both integrators to this time, recording the error of the energy
  /// (the invariant named `energy`, else the first) against t: IDA at long_run_rtol (atol =
  /// long_run_rtol × atol_scale), the variational integrator at long_run_step.
  double long_run_t_end = 0;
  double long_run_rtol = 1e-8;
  double long_run_step = 0;
  int long_run_outputs = 2000;
  /// The IDA runs (the reference run and every tolerance's), and the long run's IDA run.
  WorkPrecisionRunner runner;
};

/// One run.
struct WorkPrecisionMeasurement {
  WorkPrecisionConfiguration configuration;
  std::optional<double> sweep_value;
  double rtol = 0, atol = 0;  ///< IDA's; NaN for a variational run
  double step = 0;            ///< the variational integrator's fixed step; 0 for IDA
  double error = 0;           ///< max over output times and coordinates of |q − q_ref|; NaN when nothing to compare
  double seconds = 0;         ///< wall time of simulate() (initialization + integration), median of repeats
  int repeats = 1;
  Statistics statistics;
  double max_hidden = 0;              ///< max |g_i| over the outputs
  double max_invariant_relative = 0;  ///< max over invariants of max |I(t) − I(t0)| / |I(t0)|
  double t_reached = 0;
  std::optional<base::FailureKind> failure;
  double failure_t = 0;
  std::string failure_message;
  std::string status() const;  ///< "ok" or the failure kind with underscores
};

/// The reference a series was measured against.
struct ErrorSource {
  bool exact = false;         ///< the model's reference solution (the scene's [reference]); else a reference run
  double rtol = 0, atol = 0;  ///< of the reference run
  std::string description() const;
};

/// |I(t) − I(t0)| of one invariant along a long run of one integrator.
struct InvariantHistory {
  std::string integrator;  ///< "IDA, rtol 1e-08", "variational, step 0.01"
  std::string invariant;
  std::vector<double> t, error;
  double seconds = 0;  ///< wall time of the run
  long steps = 0;
  std::string failure;  ///< "" when the run reached its end
};

struct WorkPrecision {
  std::string scene_name, model_name;
  int n_states = 0, n_hidden = 0, n_invariants = 0;
  std::vector<std::string> state_names, hidden_names, invariant_names, singular_names;
  std::vector<std::string> parameter_names;
  std::vector<double> parameters;  ///< after overrides, before the sweep
  WorkPrecisionSettings settings;
  ErrorSource source;
  std::vector<WorkPrecisionMeasurement> measurements;
  std::vector<InvariantHistory> long_runs;  ///< WorkPrecisionSettings::long_run_t_end
};

/// Progress callback: one line of text per finished run.
using ProgressSink = std::function<void(const std::string&)>;

/// The model in the Jacobian flavours the configurations ask for: "dense" (also used for the
/// reference run) must be present, "sparse" when a configuration uses KLU.
struct WorkPrecisionModels {
  const Model* dense = nullptr;
  const Model* sparse = nullptr;
  const Model* variational = nullptr;  ///< with the variational step, for variational configurations
};

/// Runs the series from the initial data `initial_values` (per coordinate or multiplier: value,
/// first derivative, …, as initial_state_from takes them) at t0. Throws ModelError for an
/// unknown parameter in the settings or a missing model flavour.
WorkPrecision measure_work_precision(const WorkPrecisionModels& models, double t0,
                                     const std::map<std::string, std::vector<double>>& initial_values,
                                     const WorkPrecisionSettings& settings, const ProgressSink& progress = {});

}  // namespace nhc::runtime
