#pragma once
/// \file constraint_solver.hpp
/// \brief The one solver nhc uses to put values on constraints g(y) = 0: minimum-norm damped
/// Gauss–Newton. With D = diag(scale) over the free values,
///   Δy = −D (G D)^+ g,   G = ∂g/∂y,
/// the orthogonal projection in the metric D^{-2} (Hairer–Wanner, Sect. VII.2), halved until
/// |g| decreases. Values with scale 0 stay fixed.
///
/// Used for the consistent initial point by both `nhc analyze` (GiNaC-evaluated g, analysis/
/// consistent_initialization.cpp) and the runtime (the generated g, hidden_constraints.hpp), so
/// that both report the same point; and for projection during integration. It needs only
/// Eigen: the functions are callbacks.

#include <functional>
#include <vector>

namespace nhc::base {

/// One entry ∂g_row/∂y_col.
struct SparseEntry {
  int row = 0;
  int col = 0;
  double value = 0.0;
};

/// Above this many entries m·n_free the Gauss–Newton step uses the sparse Jacobian when one is given.
inline constexpr long long kSparseStepSize = 40000;

struct ConstraintFunctions {
  int count = 0;  ///< m, the number of constraints
  int size = 0;   ///< n, the number of values
  /// g(y): writes m values.
  std::function<void(const double* y, double* g)> values;
  /// ∂g/∂y: writes the m×n matrix column-major (as generated code does).
  std::function<void(const double* y, double* jacobian)> jacobian;
  /// Optional: ∂g/∂y as its nonzero entries, the others 0. When set and m·(free values) exceeds
  /// kSparseStepSize, the step is taken sparsely (solve_constraints).
  std::function<void(const double* y, std::vector<SparseEntry>& entries)> sparse_jacobian;
};

enum class ConstraintSolveStatus {
  converged,            ///< max |g_i| <= tolerance (or at its noise level, 100 tolerance)
  not_finite,           ///< g is NaN or Inf at the start
  gradient_not_finite,  ///< ∂g/∂y is NaN or Inf
  nothing_free,         ///< violated, and every value is fixed
  independent_of_free,  ///< violated, and g does not depend on any free value
  stalled,              ///< no damped step reduces |g|
  iteration_limit,      ///< max_iterations reached
};

struct ConstraintSolveResult {
  ConstraintSolveStatus status = ConstraintSolveStatus::converged;
  int iterations = 0;
  double residual_before = 0;     ///< max |g_i| before
  double residual_after = 0;      ///< max |g_i| at the returned y
  double correction = 0;          ///< max |Δy_i| in total
  std::vector<double> residuals;  ///< g at the returned y
  int worst = 0;                  ///< index of the largest |g_i| there

  bool converged() const { return status == ConstraintSolveStatus::converged; }
};

/// With a sparse Jacobian and m·n_free > kSparseStepSize the minimum-norm step is
/// (GD)ᵀ((GD)(GD)ᵀ)⁻¹g by a sparse LDLᵀ factorization of (GD)(GD)ᵀ: the same step as the dense
/// complete orthogonal decomposition when GD has full row rank, in time that follows the
/// nonzeros (a chain of N bodies: O(N) instead of O(N³)). When that factorization shows a rank
/// deficiency (a pivot below 1e-12 of the largest), the dense decomposition is used.
/// Moves the values with scale[i] > 0 until max |g_i(y)| <= tolerance. On failure y is the last
/// accepted iterate; the result says why.
ConstraintSolveResult solve_constraints(const ConstraintFunctions& g, double* y, const std::vector<double>& scale,
                                        double tolerance, int max_iterations = 50);

}  // namespace nhc::base
