#pragma once
/// \file integrator.hpp
/// \brief Integrating the index-1 form F(t, y, y') = 0 of a generated model with IDA
/// (SUNDIALS; Hindmarsh et al., ACM TOMS 31 (2005) 363): dense LU or KLU with the generated
/// Jacobian, the id vector, consistent initialization, output at requested times, events,
/// statistics, optional projection onto the hidden constraints, and diagnostics that stop at
/// singular points with the time (docs/projection.md, docs/generated-code.md).

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <optional>
#include <vector>

#include "nhc/base/errors.hpp"
#include "nhc/runtime/inputs.hpp"
#include "nhc/runtime/model.hpp"
#include "nhc/runtime/progress.hpp"

namespace nhc::runtime {

enum class LinearSolverKind {
  automatic,  ///< KLU when the model carries a sparse Jacobian, else dense LU
  dense,      ///< dense LU (generated dense Jacobian, the sparse one scattered, or difference quotients)
  sparse,     ///< KLU on the generated compressed-column Jacobian
};

/// Whether `kind` means KLU for this model: `automatic` follows what the model carries (the size
/// policy lives where the header is generated, default_jacobian_kind in the emit layer); `sparse`
/// on a model without the sparse Jacobian is a ModelError. The one rule for the integrator and the
/// sensitivities (the bench times whichever Jacobian the run's statistics say was used).
bool uses_sparse_solver(const Model& model, LinearSolverKind kind);

enum class ProjectionMethod {
  none,
  /// After a step whose hidden constraints need a correction larger than projection_threshold
  /// in IDA's weighted norm: project y (hidden_constraints.hpp), recompute y' and the algebraic
  /// states (IDACalcIC) and restart IDA there (docs/projection.md).
  restart,
  /// After such a step: project y_n and shift IDA's history (its divided difference phi[0]) by the
  /// correction, so the next step predicts from the projected point without a restart.
  in_place,
};

struct IntegratorOptions {
  double rtol = 1e-8;
  double atol = 1e-10;
  long max_steps = 1000000;  ///< internal steps over the whole run
  double max_step = 0;       ///< 0: no limit
  double initial_step = 0;   ///< 0: IDA's estimate
  LinearSolverKind linear_solver = LinearSolverKind::automatic;
  /// Include the algebraic states (d_j = 0, e.g. chetaev's λ) in IDA's local error test. Off by
  /// default: they follow from the differential states, and testing them makes stiff scenes
  /// take steps of order 1/sqrt(K) (IDASetSuppressAlg).
  bool algebraic_in_error_test = false;
  ProjectionMethod projection = ProjectionMethod::none;  ///< `--project` selects in_place
  /// Project when the correction exceeds this in IDA's WRMS norm (1 = the local error tolerance;
  /// 0 = after every step). docs/projection.md has the measurements behind the default.
  double projection_threshold = 1.0;
  /// A singular-set monitor s_k stops the run when |s_k| falls below this times |s_k(t0)|.
  double singularity_threshold = 1e-14;
  /// Told where the run stands (progress.hpp); empty: nobody. A library does not draw on its
  /// caller's terminal: `nhc simulate` passes a bar on stderr (cli/progress_bar.hpp).
  ProgressCallback progress;
  /// Asked after every accepted step (by the SensitivityIntegrator after every output and every
  /// 32 residual evaluations); true
  /// stops the run with a SolverError of kind `stopped` at the last step (the samples before it
  /// are passed on). How an interpreter's Ctrl-C ends a
  /// long run (the Python package: KeyboardInterrupt).
  std::function<bool()> stop_requested;
};

/// Initial data: a guess for every state, and which of them the user gave (these stay fixed
/// while the hidden constraints are solved; the others are moved, then IDACalcIC computes the
/// algebraic states and y').
struct InitialState {
  double t0 = 0;
  std::vector<double> y;
  std::vector<bool> given;
  std::vector<double> yp;  ///< optional guess, zeros when empty
  /// --repair-initial: given values that miss a hidden constraint move to the nearest consistent
  /// point, all but those marked in `pinned` ([initial] fixed); initial_point.hpp's one rule.
  bool repair = false;
  std::vector<bool> pinned;
};

/// Initial data in a scene's [initial] form (per coordinate or multiplier name: value, first
/// derivative, …) as an InitialState of `model`. Values of differential states are given; values
/// of algebraic states and derivatives one order above a state are only guesses.
InitialState initial_state_from(const Model& model, double t0,
                                const std::map<std::string, std::vector<double>>& values);

/// What --repair-initial may move: 1 for every state but the pinned ones (0 without repair).
std::vector<double> initial_repair_scale(const InitialState& state);

struct Sample {
  double t = 0;
  std::vector<double> y, yp;
  std::vector<double> u;  ///< the model's inputs at (t, y), n_inputs of them (inputs.hpp)
};

/// A user event: the run records (and, if terminal, stops at) each zero of `function`, located
/// by IDA's root finding (IDARootInit) to the integration tolerance.
struct Event {
  std::string name;
  std::function<double(double t, const double* y, const double* yp)> function;
  bool terminal = false;
  /// The crossings that count: +1 increasing only, -1 decreasing only, 0 both (IDASetRootDirection).
  int direction = 0;
  /// Also met at the initial point when `function` starts below zero there (a condition that
  /// fails from the start, as a contact that slips at t0); IDA reports crossings only.
  bool met_below_at_start = false;
};

struct EventHit {
  std::string name;
  double t = 0;
  std::vector<double> y, yp;  ///< the state at the crossing
};

struct Statistics {
  long steps = 0;
  long residual_evaluations = 0;  ///< including those for difference-quotient Jacobians
  long jacobian_evaluations = 0;
  long linear_solver_setups = 0;
  long error_test_failures = 0;
  long nonlinear_iterations = 0;
  long nonlinear_failures = 0;  ///< nonlinear-solver convergence failures
  long root_evaluations = 0;
  long projections = 0;
  double initialization_seconds = 0;
  double integration_seconds = 0;
  std::string linear_solver;  ///< "dense" or "KLU"
  std::string jacobian;       ///< "generated dense", "generated sparse", "difference quotients"
};

class Integrator {
 public:
  /// `parameters` empty: the model's defaults.
  Integrator(Model model, std::vector<double> parameters = {}, IntegratorOptions options = {});
  ~Integrator();
  Integrator(Integrator&&) noexcept;
  Integrator& operator=(Integrator&&) noexcept;
  Integrator(const Integrator&) = delete;
  Integrator& operator=(const Integrator&) = delete;

  /// The model's inputs (scene [inputs]; docs/runtime.md, "Inputs"): by default its default
  /// signals. set_inputs: u(t, y) from now on, evaluated at every residual and Jacobian call (a
  /// continuous feedback law). hold_inputs: u constant from now on (sampled-data control:
  /// integrate to a sampling time, read the state, hold the next u). Called between integrate()
  /// calls, both restart the integration at the last output time, so that no step taken with
  /// the old inputs is kept beyond it; before initialize(), they set the inputs it starts with.
  void set_inputs(InputFunction u);
  void hold_inputs(std::vector<double> u);

  /// The point the integration stands at (after initialize(), integrate() or a restart by
  /// set_inputs/hold_inputs, whose y' and algebraic states follow the new inputs), with its inputs.
  Sample point() const;

  /// Registers an event; call before initialize().
  void add_event(Event event);

  /// Consistent initialization at state.t0; `t_next` (> t0) is the first output time (IDACalcIC's
  /// step scale). Returns the consistent point. Throws SolverError.
  Sample initialize(const InitialState& state, double t_next);

  /// Integrates through `times` (increasing, >= t0), calling `observer` with the solution at each
  /// (times equal to t0 give the initial point). Returns after the last time or at a terminal
  /// event. Throws SolverError at a failure or a singular point, after passing the observer the
  /// last point reached (so a trajectory holds the solution up to the failure).
  void integrate(const std::vector<double>& times, const std::function<void(const Sample&)>& observer);

  Statistics statistics() const;
  const std::vector<EventHit>& events() const;
  const Model& model() const;
  const std::vector<double>& parameters() const;
  const IntegratorOptions& options() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// n + 1 equally spaced times from t0 to t_end (for any finite t0 < t_end, none overflows).
std::vector<double> output_times(double t0, double t_end, int intervals);
/// The first index i at which times[i] <= times[i - 1]: equally spaced times closer than
/// double precision resolves at their size (10^7 intervals of 1 s at t0 = 1e12) collapse.
std::optional<std::size_t> collapsed_output_time(const std::vector<double>& times);
/// The first of `times` after t0, or t0 + 1 when none is: initialize()'s t_next for a run that
/// writes at `times`.
double first_output_after(const std::vector<double>& times, double t0);

}  // namespace nhc::runtime
