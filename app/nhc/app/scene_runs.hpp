#pragma once
/// \file scene_runs.hpp
/// \brief Many runs of one scene, each at its own parameter and initial values (nhc ensemble's
/// members): each is the run `nhc simulate --set NAME=V … --initial NAME=V …` makes, through the
/// one run engine (run_engine.hpp), with the scene's events, contacts and sampled controller. The
/// values are set with the one rule of --set (set_parameter_values: the [initial] values, a
/// contact's mu, an event's threshold and the controller's laws follow them), the initial values
/// written into [initial] as --initial writes them. One compiled model (and one sliding model)
/// serves every run; runs may go on several threads at once.

#include <string>
#include <utility>
#include <vector>

#include "nhc/app/initial_values.hpp"
#include "nhc/app/run_engine.hpp"
#include "nhc/app/run_request.hpp"
#include "nhc/runtime/model.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::app {

/// The values of one run: parameters (as --set), then initial values (as --initial; a derivative
/// whose lower orders the scene does not give starts them at 0).
struct RunValues {
  std::vector<std::pair<std::string, double>> parameters;
  std::vector<InitialValue> initial;
};

/// One run's outcome and the parameters it ran with (the model's order). RunOutcome::slide is
/// null: the run's scene is gone.
struct SceneRun {
  RunOutcome outcome;
  std::vector<double> p;
};

class SceneRuns {
 public:
  /// `scene` (with its --initial values), `model` built from it, `sliding` the sliding model of
  /// its contact with on_slip = "slide" (build_sliding_model of `scene`; null when it has none),
  /// `request` the settings every run shares (t_end, tolerances, output times). The scene's
  /// model predictive control is refused (refuse_many_runs_of_mpc). The engine's refusals
  /// (check_run_features) and the request's rules (check_run_request) are the caller's.
  SceneRuns(const Scene& scene, const runtime::Model& model, const runtime::Model* sliding, RunRequest request,
            FieldNames names);

  /// The rows' times every run shares: the output times, or the controller's samples (and the
  /// point of an event that ends a run, which only that run has).
  const std::vector<double>& times() const noexcept { return times_; }

  /// The run at `values`. A value a place of the scene does not allow (mu < 0) or a bad initial
  /// value throws InputError, as --set and --initial would; a numerical failure is the outcome's
  /// (RunResult::failure). May be called from several threads at once: the symbolic work holds the
  /// symbolic lock (nhc/long_work.hpp), which the caller installs when it runs threads.
  SceneRun run(const RunValues& values) const;

  /// The run of `model` (a flavour of the model given: another Jacobian) with the parameters `p`
  /// (the model's order; the scene's parameters that differ are set as --set sets them, so its
  /// events and contacts follow) from `initial`, its rows at `times`, with the integrator's
  /// `options`: nhc report's runs at its tolerances and configurations. Not for a scene with a
  /// sampled controller (its rows are its samples: std::logic_error).
  SceneRun run_at(const runtime::Model& model, const std::vector<double>& p, const runtime::InitialState& initial,
                  const std::vector<double>& times, const runtime::IntegratorOptions& options) const;

 private:
  const Scene* scene_;
  const runtime::Model* model_;
  const runtime::Model* sliding_;
  RunRequest request_;
  FieldNames names_;
  std::vector<double> times_;
};

/// A command that runs a scene many times (`command`, "nhc ensemble") refuses its model predictive
/// control, InputError at the mpc table: its plans are solved by IPOPT, which only nhc-optimize
/// loads, and each run would derive the horizon problem again.
void refuse_many_runs_of_mpc(const Scene& scene, const std::string& command);

/// Where a run reads the parameter `name` beyond its model's equations and [initial]: the scene's
/// [events], its contacts' normal forces and mu, its [controller]'s laws and states' start values
/// (what the engine evaluates at each run's parameters), each as "WHAT (FILE:LINE:COLUMN)".
std::vector<std::string> run_places_reading(const Scene& scene, const std::string& name);

}  // namespace nhc::app
