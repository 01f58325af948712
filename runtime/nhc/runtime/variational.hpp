#pragma once
/// \file variational.hpp
/// \brief Integrating a generated model with its discrete Lagrange–d'Alembert step
/// (docs/variational.md): a fixed step h, Newton's method on the generated residual and
/// Jacobian at every step, the samples in the states of the IDA path.
///
/// The step (Variational additions of docs/generated-code.md) gives the increment q_{k+1} − q_k
/// and λ_k from q_k, the previous increment and the discrete momentum m_k; q is summed from the
/// increments with Kahan's compensation. A sample between two nodes interpolates q by the cubic
/// Hermite polynomial through (q_k, v_k) and (q_{k+1}, v_{k+1}), with the node velocities
/// v_k = (q_{k+1} − q_{k−1})/(2h), and λ and q'' linearly; at a node it is the node itself.

#include <functional>
#include <vector>

#include "nhc/runtime/integrator.hpp"
#include "nhc/runtime/trajectory.hpp"

namespace nhc::runtime {

struct VariationalOptions {
  double step = 0;  ///< h > 0
  /// Steps over the whole run; a run that needs more is refused before its first step.
  long max_steps = 1000000;
  int max_newton_iterations = 20;
  /// Newton has converged when every correction |Δx_i| ≤ newton_tolerance (1 + |x_i|).
  double newton_tolerance = 1e-12;
  /// The consistent initial point is IDA's (IntegratorOptions::rtol, atol).
  IntegratorOptions initialization;
  ProgressCallback progress;             ///< as IntegratorOptions::progress
  std::function<bool()> stop_requested;  ///< as IntegratorOptions::stop_requested, asked every step
};

/// The options of a variational run with step h and at most `max_steps` steps that otherwise
/// follows IDA's options `ida`: its tolerances for the consistent initial point, its progress callback
/// and its stop request.
VariationalOptions variational_options(double step, long max_steps, const IntegratorOptions& ida);

/// What a variational run gives besides the samples.
struct VariationalRun {
  RunResult run;
  /// max over the steps of |C_α|, the discrete constraints the step solves (order 1 at the step's
  /// midpoint, order 0 at its end): rounding level when Newton converged.
  double max_discrete_constraint = 0;
  long steps = 0;
};

/// The steps a run from t0 to t_end takes with a step of at most h: N = ceil((t_end − t0)/h) equal
/// steps of (t_end − t0)/N, so that the last node is t_end (a t_end within rounding of a node
/// counts as that node); -1 when N is beyond counting.
long variational_steps_needed(double t0, double t_end, double h);

/// Whether h fits the run from t0 to t_end at least twice, (t_end − t0)/h >= 2: the last node's
/// velocity is a backward difference over its two steps (docs/variational.md, "Samples").
bool variational_step_fits(double t0, double t_end, double h);

/// Runs `model` (generated with the variational step: Model::has_variational_step, else a
/// ModelError) from `initial` through `times`. Failures (no consistent initial point, Newton not
/// converging, a non-finite residual, the step limit, a stop request) are kept in
/// run.failure with the samples before them.
VariationalRun simulate_variational(const Model& model, const std::vector<double>& p, const InitialState& initial,
                                    const std::vector<double>& times, const VariationalOptions& options,
                                    const InputFunction& inputs = {});

}  // namespace nhc::runtime
