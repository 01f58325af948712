#pragma once
/// \file errors.hpp
/// \brief What the runtime throws. Every failure says what failed, in words, and at which t.
///
/// The command line maps SolverError to exit code 3 (a numerical failure); ModelError is a
/// model that does not fit the contract of docs/generated-code.md (internal error).

#include <limits>
#include <stdexcept>
#include <string>

namespace nhc::base {

/// Why an integration stopped.
enum class FailureKind {
  setup,                         ///< a SUNDIALS object could not be created or configured
  inconsistent_initial_values,   ///< no consistent initial point near the given values
  nonfinite_residual,            ///< NaN or Inf in a residual
  singular_iteration_matrix,     ///< the index-1 system Jacobian is singular
  singular_constraint_gradient,  ///< a constraint gradient is singular or undefined (e.g. v -> 0)
  convergence,                   ///< the corrector does not converge, step size underflow
  error_test,                    ///< repeated local error test failures
  too_many_steps,                ///< the step limit was reached
  stopped,                       ///< IntegratorOptions::stop_requested said so (an interrupt)
  other,
};

/// Short name of a failure kind ("singular iteration matrix").
const char* to_string(FailureKind kind);

/// A model does not satisfy the contract (wrong ABI version, missing residual, bad sizes).
class ModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A numerical failure at time t (NaN when no time applies, e.g. while creating objects).
class SolverError : public std::runtime_error {
 public:
  SolverError(FailureKind kind, double t, const std::string& message)
      : std::runtime_error(message), kind_(kind), t_(t) {}
  FailureKind kind() const noexcept { return kind_; }
  double t() const noexcept { return t_; }

 private:
  FailureKind kind_;
  double t_;
};

inline constexpr double kNoTime = std::numeric_limits<double>::quiet_NaN();

}  // namespace nhc::base
