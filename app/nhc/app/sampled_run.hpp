#pragma once
/// \file sampled_run.hpp
/// \brief A sampled (discrete-time) controller (docs/scenes.md, "Sampled controllers"): its
/// sample times and the scene's [controller] laws. The run engine (run_engine.hpp) runs it: at
/// each sample t_k = t0 + k h (computed so, not accumulated) the controller reads the state the
/// run reached, returns the inputs it holds until the next sample (zero-order hold), and the
/// integrator restarts exactly there: the states stay, y' and the algebraic states are
/// recomputed for the new inputs.

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "nhc/app/run_request.hpp"
#include "nhc/app/sample_expressions.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::app {

/// One sample of a controller: from the point the run reached at t_k (at t0 the consistent
/// initial point under the inputs' default signals), the model's inputs (all of them, in the
/// model's order) to hold from t_k on. The controller keeps and advances its own state.
using SampleLaw = std::function<std::vector<double>(const runtime::Sample& reached)>;

/// The sample times t0 + k period, k = 0 … N with N = floor((t_end − t0)/period + 1e-9): the run
/// ends at the last sample at or before t_end. InputError at `where` (the period, named `what`)
/// when it is not a positive finite number, does not fit once, or gives more than kMaxOutputs
/// samples.
std::vector<double> sample_times(double t0, double t_end, double period, const SourceLocation& where,
                                 const std::string& what);

/// A run under the scene's [controller]: its rows are the samples (and the point of an event
/// that ends the run), so `outputs`, `output_times` and the variational integrator are refused (InputError at the
/// field, in `names`' words); the sample times from t0 to the request's t_end, else [simulate]'s.
std::vector<double> scene_controller_samples(const RunRequest& request, const Scene& scene, const FieldNames& names);

/// Commands that do not run a sampled controller (report, compare) refuse a
/// scene with one rather than run it open loop: InputError at the [controller] table.
void refuse_scene_controller(const Scene& scene, const std::string& command);

/// The scene's [controller] on a model: its input laws and updates evaluated at the samples.
/// Inputs it does not set follow their default signals.
class ControllerLaws {
 public:
  /// InputError at the expression for a quantity the model's states do not hold (an
  /// acceleration, x'' of a second-order system), or an input the model does not read.
  ControllerLaws(const Scene& scene, const runtime::Model& model, const std::vector<double>& p);

  /// Which of the model's inputs the controller sets (RunControl::held, run_engine.hpp).
  const std::vector<bool>& held() const noexcept { return held_; }
  /// The column names of the discrete states ("controller:z"), in the scene's order.
  const std::vector<std::string>& state_columns() const noexcept { return columns_; }
  /// The discrete states' values at each sample the law was called at (z_k), in call order.
  const std::vector<std::vector<double>>& state_history() const noexcept { return history_; }
  /// The discrete states now (after the last call's update: those the next call reads).
  const std::vector<double>& state() const noexcept { return z_; }

  /// u_k from (t_k, y(t_k), z_k), then z_{k+1} = update(t_k, y(t_k), z_k).
  std::vector<double> operator()(const runtime::Sample& reached);

 private:
  const Scene* scene_;
  const runtime::Model* model_;
  std::vector<double> p_;
  SampleExpressions expressions_;  ///< the input laws, then the updates
  std::vector<int> input_slots_;   ///< per input law: the model's input index
  std::vector<bool> held_;
  std::vector<double> z_;
  std::vector<std::string> columns_;
  std::vector<std::vector<double>> history_;
};

/// A SampleLaw calling `law` (shared: the caller reads its state history afterwards).
SampleLaw sample_law(std::shared_ptr<ControllerLaws> law);

}  // namespace nhc::app
