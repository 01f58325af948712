#include "nhc/base/errors.hpp"

namespace nhc::base {

const char* to_string(FailureKind kind) {
  switch (kind) {
    case FailureKind::setup:
      return "solver set-up failure";
    case FailureKind::inconsistent_initial_values:
      return "inconsistent initial values";
    case FailureKind::nonfinite_residual:
      return "NaN or Inf in a residual";
    case FailureKind::singular_iteration_matrix:
      return "singular iteration matrix";
    case FailureKind::singular_constraint_gradient:
      return "singular constraint gradient";
    case FailureKind::convergence:
      return "convergence failure";
    case FailureKind::error_test:
      return "error test failure";
    case FailureKind::too_many_steps:
      return "too many steps";
    case FailureKind::stopped:
      return "stopped";
    case FailureKind::other:
      break;
  }
  return "numerical failure";
}

}  // namespace nhc::base
