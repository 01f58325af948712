#pragma once
/// \file solve.hpp
/// \brief The transcribed problem (hermite_simpson.hpp) solved by IPOPT with exact or
/// limited-memory quasi-Newton Hessians (docs/optimize.md, "Solver"), and IPOPT's status in words.

#include <functional>
#include <string>
#include <vector>

#include "nhc/optimize/hermite_simpson.hpp"

namespace nhc::optimize {

struct SolveOptions {
  int max_iterations = 3000;
  double tolerance = 1e-10;           ///< IPOPT's tol: the scaled KKT error at the optimum
  double violation_tolerance = 1e-9;  ///< IPOPT's constr_viol_tol: the largest |constraint| at the optimum
  /// IPOPT's acceptable_iter: this many iterates in a row that meet the acceptable optimality
  /// tolerance (1e-6) and the violation tolerance stop the solve (Solution::Status::acceptable).
  int acceptable_iterations = 15;
  /// IPOPT differentiates the constraints itself by finite differences on the exact Jacobian's
  /// structure (jacobian_approximation = finite-difference-values) instead of taking the exact
  /// values: what the exact derivatives buy (bench/optimize.md).
  bool finite_difference_jacobian = false;
  /// The exact Hessian of the Lagrangian (HermiteSimpson::hessian_values), else IPOPT's
  /// limited-memory quasi-Newton approximation (hessian_approximation = limited-memory).
  bool exact_hessian = true;
  /// Called after each iteration with its number, the objective and the constraint violation;
  /// returning false stops the solve (a user's interrupt).
  std::function<bool(int iteration, double cost, double violation)> progress;
};

struct Solution {
  /// acceptable: IPOPT stopped at a point that meets only its looser acceptable_tol (1e-6).
  enum class Status { optimal, iteration_limit, acceptable, infeasible, failed } status = Status::failed;
  std::string words;      ///< IPOPT's status in words (empty when optimal)
  std::vector<double> z;  ///< the last point: the optimum, or the best IPOPT reached
  double cost = 0;
  double violation = 0;  ///< the largest |constraint| at z
  std::string worst;     ///< the constraint of that violation, in words (constraint_name)
  int iterations = 0;
};

Solution solve(HermiteSimpson& problem, const std::vector<double>& guess, const SolveOptions& options = {});

}  // namespace nhc::optimize
