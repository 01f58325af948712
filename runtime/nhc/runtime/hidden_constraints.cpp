#include "nhc/runtime/hidden_constraints.hpp"

#include <Eigen/Dense>

#include <cmath>
#include <sstream>

#include "nhc/runtime/errors.hpp"

namespace nhc::runtime {

double hidden_residual(const Model& model, const double* p, double t, const double* y) {
  const int m = model.n_hidden();
  if (m == 0) return 0.0;
  std::vector<double> g(m);
  model.table().hidden_constraints(t, y, p, g.data());
  double worst = 0;
  for (double gi : g) worst = std::isfinite(gi) ? std::max(worst, std::abs(gi)) : INFINITY;
  return worst;
}

HiddenSolveReport solve_hidden_constraints(const Model& model, const double* p, double t, double* y,
                                           const std::vector<double>& scale, double tolerance,
                                           int max_iterations) {
  HiddenSolveReport report;
  const int m = model.n_hidden(), n = model.n_states();
  if (m == 0) return report;
  const auto& tab = model.table();

  std::vector<int> free;
  for (int i = 0; i < n; ++i)
    if (scale[i] > 0) free.push_back(i);
  const int nf = static_cast<int>(free.size());

  Eigen::VectorXd g(m);
  Eigen::MatrixXd G(m, n);  // column-major, as the generated code writes it
  auto evaluate = [&] {
    tab.hidden_constraints(t, y, p, g.data());
    return g.allFinite() ? g.cwiseAbs().maxCoeff() : INFINITY;
  };
  auto describe = [&](const std::string& why) {
    std::ostringstream os;
    os.precision(17);
    int worst = 0;
    g.cwiseAbs().maxCoeff(&worst);
    os << "no consistent initial values at t = " << t << ": " << why << "; hidden constraint "
       << model.hidden_name(worst) << " = " << g[worst] << ". States that may be changed: ";
    if (free.empty()) os << "none (every state was given)";
    for (int k = 0; k < nf; ++k) os << (k ? ", " : "") << model.state_name(free[k]);
    os << ". Give fewer or consistent initial values.";
    return os.str();
  };

  double res = evaluate();
  report.residual_before = res;
  if (!std::isfinite(res)) throw SolverError(FailureKind::inconsistent_initial_values, t, describe("a hidden constraint is not finite"));
  while (res > tolerance) {
    if (report.iterations >= max_iterations)
      throw SolverError(FailureKind::inconsistent_initial_values, t,
                        describe("Gauss–Newton did not converge in " + std::to_string(max_iterations) + " iterations"));
    if (nf == 0) throw SolverError(FailureKind::inconsistent_initial_values, t, describe("the initial values violate it"));
    tab.hidden_constraints_jacobian(t, y, p, G.data());
    if (!G.allFinite())
      throw SolverError(FailureKind::singular_constraint_gradient, t,
                        describe("the hidden-constraint gradient is not defined (NaN/Inf) at the initial point"));
    Eigen::MatrixXd A(m, nf);
    for (int k = 0; k < nf; ++k) A.col(k) = G.col(free[k]) * scale[free[k]];
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(A);
    cod.setThreshold(1e-12);
    if (cod.rank() == 0)
      throw SolverError(FailureKind::inconsistent_initial_values, t,
                        describe("the hidden constraints do not depend on any state that may be changed"));
    Eigen::VectorXd u = cod.solve(g);
    // Damped step: halve until the residual decreases (guards against overshooting a sqrt).
    std::vector<double> y0(y, y + n);
    double lambda = 1.0, trial = INFINITY;
    for (int half = 0; half < 30; ++half) {
      for (int k = 0; k < nf; ++k) y[free[k]] = y0[free[k]] - lambda * scale[free[k]] * u[k];
      trial = evaluate();
      if (trial < res) break;
      lambda *= 0.5;
    }
    ++report.iterations;
    if (!(trial < res)) {
      std::copy(y0.begin(), y0.end(), y);
      evaluate();
      if (res <= 100 * tolerance) break;  // at the noise level of the constraint
      throw SolverError(FailureKind::inconsistent_initial_values, t,
                        describe("Gauss–Newton stalls (the free states cannot reduce the violation)"));
    }
    for (int k = 0; k < nf; ++k) report.correction = std::max(report.correction, std::abs(y[free[k]] - y0[free[k]]));
    res = trial;
  }
  report.residual_after = res;
  return report;
}

}  // namespace nhc::runtime
