#pragma once
/// \file optimize_request.hpp
/// \brief `nhc optimize` as a front end asks for it (the command line's flags, Python's
/// Scene.optimize arguments) and its rules in one place: the intervals, IPOPT's iteration limit
/// and tolerance, the Jacobian and the Hessian (docs/optimize.md, "Solver").

#include <optional>
#include <string>

namespace nhc::app {

inline constexpr long long kMaxIntervals = 100000;
inline constexpr long long kMaxIterations = 1000000;

/// How a front end names the fields in its messages.
struct OptimizeFieldNames {
  std::string intervals, max_iterations, tolerance, jacobian, hessian, path_tolerance;
};
const OptimizeFieldNames& optimize_command_line_names();
const OptimizeFieldNames& optimize_python_names();

struct OptimizeRequest {
  std::optional<long long> intervals;  ///< none: [optimize] intervals
  long long max_iterations = 3000;
  double tolerance = 1e-10;        ///< IPOPT's tol
  std::string jacobian = "exact";  ///< exact | finite-differences
  std::string hessian = "exact";   ///< exact | limited-memory
  double path_tolerance = 1e-6;    ///< the largest path error accepted (docs/optimize.md, "Path error")
};

/// Every rule of the request: InputError at the field (in `names`) otherwise.
void check_optimize_request(const OptimizeRequest& request, const OptimizeFieldNames& names);

/// The solver's choices of a request, typed: where the Jacobian and the Hessian come from.
enum class JacobianChoice { exact, finite_differences };
enum class HessianChoice { exact, limited_memory };
struct OptimizeChoices {
  int max_iterations = 3000;
  double tolerance = 1e-10;
  JacobianChoice jacobian = JacobianChoice::exact;
  HessianChoice hessian = HessianChoice::exact;
  double path_tolerance = 1e-6;
};

/// The request's choices (after check_optimize_request, which refuses names it does not know);
/// app/nhc/app/optimize_options.hpp turns them into the solver's options for both front ends.
OptimizeChoices optimize_choices(const OptimizeRequest& request);

}  // namespace nhc::app
