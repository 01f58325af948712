#include "nhc/runtime/hidden_constraints.hpp"

#include <cmath>
#include <sstream>

#include "nhc/base/constraint_solver.hpp"
#include "nhc/base/errors.hpp"
#include "nhc/base/number_text.hpp"

namespace nhc::runtime {

namespace {

/// The model's hidden constraints g(t, y; p) at time t as the constraint solver takes them.
base::ConstraintFunctions hidden_constraint_functions(const Model& model, const double* p, double t) {
  const auto& tab = model.table();
  base::ConstraintFunctions g;
  g.count = model.n_hidden();
  g.size = model.n_states();
  g.values = [&tab, p, t](const double* y, double* out) { tab.hidden_constraints(t, y, p, out); };
  g.jacobian = [&tab, p, t](const double* y, double* out) { tab.hidden_constraints_jacobian(t, y, p, out); };
  return g;
}

HiddenSolveReport report_of(const base::ConstraintSolveResult& r) {
  HiddenSolveReport report;
  report.iterations = r.iterations;
  report.residual_before = r.residual_before;
  report.residual_after = r.residual_after;
  report.correction = r.correction;
  return report;
}

}  // namespace

HiddenSolveReport solve_hidden_constraints(const Model& model, const double* p, double t, double* y,
                                           const std::vector<double>& scale, double tolerance, int max_iterations) {
  const int n = model.n_states();
  if (model.n_hidden() == 0) return {};
  const base::ConstraintSolveResult r =
      base::solve_constraints(hidden_constraint_functions(model, p, t), y, scale, tolerance, max_iterations);
  if (r.converged()) return report_of(r);

  auto describe = [&](const std::string& why) {
    std::ostringstream os;
    os << "no consistent initial values at t = " << base::number_text(t, 17) << ": " << why << "; hidden constraint "
       << model.hidden_name(r.worst) << " = " << base::number_text(r.residuals[static_cast<std::size_t>(r.worst)], 17)
       << ". States that may be changed: ";
    bool any = false;
    for (int i = 0; i < n; ++i)
      if (scale[static_cast<std::size_t>(i)] > 0) {
        os << (any ? ", " : "") << model.state_name(i);
        any = true;
      }
    if (!any) os << "none (every state was given)";
    os << ". Give fewer or consistent initial values.";
    return os.str();
  };
  switch (r.status) {
    case base::ConstraintSolveStatus::converged:
      break;
    case base::ConstraintSolveStatus::not_finite:
      throw base::SolverError(base::FailureKind::inconsistent_initial_values, t,
                              describe("a hidden constraint is not finite"));
    case base::ConstraintSolveStatus::gradient_not_finite:
      throw base::SolverError(base::FailureKind::singular_constraint_gradient, t,
                              describe("the hidden-constraint gradient is not defined (NaN/Inf) at the initial point"));
    case base::ConstraintSolveStatus::nothing_free:
      throw base::SolverError(base::FailureKind::inconsistent_initial_values, t,
                              describe("the initial values violate it"));
    case base::ConstraintSolveStatus::independent_of_free:
      throw base::SolverError(base::FailureKind::inconsistent_initial_values, t,
                              describe("the hidden constraints do not depend on any state that may be changed"));
    case base::ConstraintSolveStatus::stalled:
      throw base::SolverError(base::FailureKind::inconsistent_initial_values, t,
                              describe("Gauss–Newton stalls (the free states cannot reduce the violation)"));
    case base::ConstraintSolveStatus::iteration_limit:
      throw base::SolverError(
          base::FailureKind::inconsistent_initial_values, t,
          describe("Gauss–Newton did not converge in " + std::to_string(max_iterations) + " iterations"));
  }
  return report_of(r);
}

HiddenSolveReport solve_initial_hidden_constraints(const Model& model, const double* p, double t0, double* y,
                                                   const std::vector<double>& scale,
                                                   const base::InitialPointTolerance& tolerance, int max_iterations,
                                                   const std::vector<double>* repair_scale) {
  const int m = model.n_hidden(), n = model.n_states();
  if (m == 0) return {};
  const auto& tab = model.table();
  const base::InitialPointSolve solve = base::solve_or_repair_initial_point(
      hidden_constraint_functions(model, p, t0), y, scale, repair_scale, tolerance, max_iterations);
  const base::ConstraintSolveResult& r = solve.result;
  const std::vector<double>& moved = solve.repaired ? *repair_scale : scale;
  if (r.converged()) return report_of(r);

  base::InconsistentInitialPoint failure;
  failure.model = model.model_name();
  failure.constraint = "hidden constraint " + model.hidden_name(r.worst);
  failure.residual = r.residuals.empty() ? r.residual_after : r.residuals[static_cast<std::size_t>(r.worst)];
  failure.t0 = t0;
  failure.tolerance = tolerance;
  failure.status = r.status;
  std::vector<double> jacobian(static_cast<std::size_t>(m) * static_cast<std::size_t>(n));
  tab.hidden_constraints_jacobian(t0, y, p, jacobian.data());
  for (int i = 0; i < n; ++i) {
    const double entry =
        jacobian[static_cast<std::size_t>(i) * static_cast<std::size_t>(m) + static_cast<std::size_t>(r.worst)];
    if (entry == 0.0) continue;
    if (moved[static_cast<std::size_t>(i)] > 0) failure.free.push_back(model.state_name(i));
    else failure.given.push_back({model.state_name(i), y[i]});
  }
  const base::FailureKind kind = r.status == base::ConstraintSolveStatus::gradient_not_finite
                                     ? base::FailureKind::singular_constraint_gradient
                                     : base::FailureKind::inconsistent_initial_values;
  throw base::SolverError(kind, t0, describe(failure));
}

void solve_starting_point(const Model& model, const double* p, double t0, double* y, const std::vector<bool>& given,
                          double rtol, double atol, const std::vector<double>* repair_scale) {
  if (model.n_hidden() == 0) return;
  const int n = model.n_states();
  std::vector<double> scale(static_cast<std::size_t>(n), 1.0);
  for (int i = 0; i < n && i < static_cast<int>(given.size()); ++i)
    if (given[static_cast<std::size_t>(i)]) scale[static_cast<std::size_t>(i)] = 0.0;
  std::vector<double> differential;
  for (int i = 0; i < n; ++i)
    if (model.is_differential(i)) differential.push_back(y[i]);
  solve_initial_hidden_constraints(model, p, t0, y, scale, base::initial_point_tolerance(differential, rtol, atol), 50,
                                   repair_scale);
}

}  // namespace nhc::runtime
