#pragma once
/// \file shooting.hpp
/// \brief nhc::connect — boundary-value problems by shooting (docs/connect.md): find the free
/// initial values θ so that chosen states reach target values at T,
///   r(θ) = y_c(T; θ) − target = 0,
/// by Newton's method with the forward sensitivities ∂y(T)/∂θ from IDAS as the Jacobian
/// (runtime/sensitivity.hpp) and a backtracking line search on |r|. With K segments (multiple
/// shooting) the states at the inner nodes are unknowns too and continuity at the nodes joins
/// the conditions. Steps are J⁺ r (complete orthogonal decomposition): the minimum-norm step
/// when there are more unknowns than conditions, the least-squares step when fewer.
///
///   const auto loaded = nhc::jit::build(scene, nhc::ModelKind::vakonomic, {std::nullopt, true});
///   nhc::connect::ShootingProblem problem{loaded.model(), ...};
///   const nhc::connect::ShootingResult found = nhc::connect::connect(problem);

#include <stdexcept>
#include <string>
#include <vector>

#include "nhc/runtime/runtime.hpp"

namespace nhc::connect {

/// y_state(T) = value.
struct Condition {
  int state = 0;
  std::string name;  ///< the state's name, "x"
  double value = 0;
};

struct ShootingProblem {
  runtime::Model model;            ///< generated with its Jacobian (dF/dp is not needed)
  std::vector<double> parameters;  ///< empty: the model's defaults
  /// The given initial data (runtime::initial_state_from); the free states' values are the
  /// starting guesses and are overwritten.
  runtime::InitialState initial;
  std::vector<int> free_states;  ///< differential states whose initial values are sought
  std::vector<Condition> conditions;
  double t_end = 1;
  int segments = 1;  ///< K ≥ 1: multiple shooting on K equal intervals
  runtime::IntegratorOptions integrator;
  double tolerance = 1e-9;  ///< converged when max |r_i| ≤ tolerance (1 + |target_i|)
  int max_iterations = 50;
  int outputs = 200;  ///< trajectory samples over [t0, T]
};

struct Iteration {
  int number = 0;   ///< 0: the starting guess
  double miss = 0;  ///< max |r_i| (targets and, with segments, the continuity defects)
  double step = 0;  ///< line-search factor of the Newton step that led here (0 for number 0)
  int rank = 0;     ///< rank of the shooting Jacobian at this point
};

struct ShootingResult {
  std::vector<double> values;  ///< the free initial values found, in free_states order
  double miss = 0;
  std::vector<Iteration> history;
  bool minimum_norm = false;   ///< more unknowns than conditions: minimum-norm Newton steps
  bool least_squares = false;  ///< fewer unknowns than conditions: Gauss–Newton steps
  std::vector<runtime::Sample> trajectory;
  runtime::Statistics last_run;  ///< the final trajectory's integrator statistics (last segment)
};

/// Why no solution was found: Newton did not converge (the best miss and the history are kept),
/// or the shooting Jacobian is singular (`uninfluential` names the free values whose change does
/// not move the target at all).
class ShootingFailure : public std::runtime_error {
 public:
  enum class Kind { no_convergence, singular };
  ShootingFailure(Kind kind, const std::string& message, std::vector<Iteration> history,
                  std::vector<std::string> uninfluential, std::vector<double> best)
      : std::runtime_error(message),
        kind_(kind),
        history_(std::move(history)),
        uninfluential_(std::move(uninfluential)),
        best_(std::move(best)) {}
  Kind kind() const noexcept { return kind_; }
  const std::vector<Iteration>& history() const noexcept { return history_; }
  const std::vector<std::string>& uninfluential() const noexcept { return uninfluential_; }
  const std::vector<double>& best() const noexcept { return best_; }

 private:
  Kind kind_;
  std::vector<Iteration> history_;
  std::vector<std::string> uninfluential_;
  std::vector<double> best_;
};

/// Solves the problem. Throws ShootingFailure, base::SolverError (an integration that fails
/// at the starting guess), std::invalid_argument (an inconsistent problem: a free state that is
/// algebraic or given twice, T ≤ t0, no conditions).
ShootingResult connect(const ShootingProblem& problem);

/// The default free values: every differential state (an initial value Pryce's Σ-method needs)
/// that `initial` does not give, less those the hidden constraints then fix (chosen by
/// column-pivoted QR of the constraint Jacobian at the starting guess).
std::vector<int> default_free_states(const runtime::Model& model, const std::vector<double>& parameters,
                                     const runtime::InitialState& initial);

/// "x(0)", "x'(0)", "lambda1(0)": the name of a free state.
std::string free_value_name(const runtime::Model& model, int state);

}  // namespace nhc::connect
