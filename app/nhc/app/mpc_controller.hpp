#pragma once
/// \file mpc_controller.hpp
/// \brief Model predictive control (docs/mpc.md): the scene's [optimize] problem solved at each
/// sample of the run from the state it reached, over a receding horizon, its first input held
/// to the next sample. The nonlinear program (structure, sparsity, the derivative programs of
/// the transcription) is built once; each solve is warm-started from the last plan shifted by
/// one period. A library of its own (nhc::app_mpc): it links IPOPT, which the programs without
/// model predictive control do not load (cli/command_programs.hpp).

#include <memory>
#include <string>
#include <vector>

#include "nhc/app/sampled_run.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::optimize {
class HermiteSimpson;
}

namespace nhc::app {

/// One solve of the controller, at sample time t.
struct MpcSolve {
  double t = 0;
  double cost = 0;  ///< the plan's cost (the last iterate's when not converged)
  int iterations = 0;
  double seconds = 0;  ///< wall time of the solve
  bool converged = false;
};

class MpcController {
 public:
  /// The NLP of `scene`'s [optimize] table (objective, final_cost, [optimize.bounds],
  /// [optimize.final] as terminal conditions; its t_end and [optimize.initial] do not apply) on
  /// `mpc.intervals` equal intervals of `mpc.horizon`, the differential states of its first point
  /// the state measured at each sample. `scene` is the run's (with --set values): the problem
  /// takes its parameter values. InputError at the `mpc` entry for a scene without [optimize] or
  /// [inputs], or whose problem's states the run model does not hold.
  MpcController(const Scene& scene, const runtime::Model& model, const SceneMpc& mpc);
  ~MpcController();
  MpcController(const MpcController&) = delete;
  MpcController& operator=(const MpcController&) = delete;

  /// The inputs it sets (RunControl::held): every [inputs] input that is not a feedback law.
  const std::vector<bool>& held() const noexcept { return held_; }
  /// The columns of each row: mpc:cost, mpc:iterations, mpc:seconds.
  static const std::vector<std::string>& columns();
  /// The values of columns() for the last solve; NaN for a row that is no sample (`at_sample` false).
  std::vector<double> column_values(bool at_sample) const;
  const std::vector<MpcSolve>& solves() const noexcept { return solves_; }
  /// "model predictive control: K solves, median S s, max S s, N not converged (iterations: median I, max I)".
  std::string summary() const;

  /// The solve at the point `reached`: the model's inputs to hold from there.
  std::vector<double> operator()(const runtime::Sample& reached);

 private:
  /// `plan` (solved from plan_t0) moved to the horizon from t.
  std::vector<double> shifted_plan(const std::vector<double>& plan, double plan_t0, double t) const;
  std::vector<double> plan_inputs(double t) const;

  const runtime::Model* model_;
  SceneMpc settings_;
  std::unique_ptr<optimize::HermiteSimpson> problem_;
  std::vector<int> start_states_;  ///< per fixed slot of the first point: the run model's state index
  std::vector<int> input_slots_;   ///< per input of the problem: the model's input index (-1: not set)
  std::vector<bool> held_;
  std::vector<double> plan_;  ///< the last converged solve's variables (empty: none yet)
  double plan_t0_ = 0;
  std::vector<double> iterate_;  ///< before any converged solve: the last iterate (a warm start)
  double iterate_t0_ = 0;
  std::vector<MpcSolve> solves_;
};

/// A SampleLaw calling `controller` (shared: the caller reads its solves afterwards).
SampleLaw sample_law(std::shared_ptr<MpcController> controller);

}  // namespace nhc::app
