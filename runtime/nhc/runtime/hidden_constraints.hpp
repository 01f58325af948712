#pragma once
/// \file hidden_constraints.hpp
/// \brief Solving the hidden constraints g(t, y) = 0 of the index-1 form (models.md, step 5)
/// for some of the states: consistent initial values and projection during integration.
///
/// The minimum-norm Gauss–Newton of constraint_solver.hpp on the model's generated g and ∂g/∂y
/// (with scale = the error-weight inverse atol + rtol|y| it is the smallest correction in IDA's
/// own norm). States with scale 0 stay fixed (the user-given initial values).

#include <string>
#include <vector>

#include "nhc/base/initial_point.hpp"
#include "nhc/runtime/model.hpp"

namespace nhc::runtime {

struct HiddenSolveReport {
  int iterations = 0;
  double residual_before = 0;  ///< max |g_i| before
  double residual_after = 0;   ///< max |g_i| after
  double correction = 0;       ///< max |Δy_i|
};

/// Moves the states with scale[i] > 0 so that g(t, y) = 0 (|g_i| <= tolerance).
/// Throws SolverError(inconsistent_initial_values, t) naming the violated constraint and the
/// free states when no such point is found (e.g. every state the constraint involves is fixed).
HiddenSolveReport solve_hidden_constraints(const Model& model, const double* p, double t, double* y,
                                           const std::vector<double>& scale, double tolerance, int max_iterations = 50);

/// The consistent initial point: the states with scale[i] > 0 are solved from g(t0, y) = 0,
/// the given ones (scale 0) accepted within tolerance.accept (initial_point.hpp). Throws
/// SolverError(inconsistent_initial_values, t0) with initial_point.hpp's message otherwise.
/// With `repair_scale` the given values are repaired when they miss (solve_or_repair_initial_point).
HiddenSolveReport solve_initial_hidden_constraints(const Model& model, const double* p, double t0, double* y,
                                                   const std::vector<double>& scale,
                                                   const base::InitialPointTolerance& tolerance,
                                                   int max_iterations = 50,
                                                   const std::vector<double>* repair_scale = nullptr);

/// The starting point of every IDA run, plain or with sensitivities: the states `given` marks
/// stay, the others are moved onto g(t0, y) = 0 by solve_initial_hidden_constraints, with
/// initial_point_tolerance over the differential states (the values `nhc analyze` sees) and the
/// run's rtol and atol; with `repair_scale` (--repair-initial) the given values are repaired when
/// they miss. Nothing to do without hidden constraints.
void solve_starting_point(const Model& model, const double* p, double t0, double* y, const std::vector<bool>& given,
                          double rtol, double atol, const std::vector<double>* repair_scale = nullptr);

}  // namespace nhc::runtime
