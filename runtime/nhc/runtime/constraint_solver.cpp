#include "nhc/runtime/constraint_solver.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace nhc::runtime {

ConstraintSolveResult solve_constraints(const ConstraintFunctions& functions, double* y,
                                        const std::vector<double>& scale, double tolerance, int max_iterations) {
  ConstraintSolveResult result;
  const int m = functions.count, n = functions.size;
  if (m == 0) return result;

  std::vector<int> free;
  for (int i = 0; i < n; ++i)
    if (scale[static_cast<std::size_t>(i)] > 0) free.push_back(i);
  const int nf = static_cast<int>(free.size());

  Eigen::VectorXd g(m);
  Eigen::MatrixXd G(m, n);
  auto evaluate = [&] {
    functions.values(y, g.data());
    return g.allFinite() ? g.cwiseAbs().maxCoeff() : INFINITY;
  };
  auto finish = [&](ConstraintSolveStatus status, double residual) {
    result.status = status;
    result.residual_after = residual;
    result.residuals.assign(g.data(), g.data() + m);
    Eigen::Index worst = 0;
    if (g.allFinite()) g.cwiseAbs().maxCoeff(&worst);
    result.worst = static_cast<int>(worst);
    return result;
  };

  double res = evaluate();
  result.residual_before = res;
  if (!std::isfinite(res)) return finish(ConstraintSolveStatus::not_finite, res);
  while (res > tolerance) {
    if (result.iterations >= max_iterations) return finish(ConstraintSolveStatus::iteration_limit, res);
    if (nf == 0) return finish(ConstraintSolveStatus::nothing_free, res);
    functions.jacobian(y, G.data());
    if (!G.allFinite()) return finish(ConstraintSolveStatus::gradient_not_finite, res);
    Eigen::MatrixXd A(m, nf);
    for (int k = 0; k < nf; ++k) A.col(k) = G.col(free[k]) * scale[static_cast<std::size_t>(free[k])];
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(A);
    cod.setThreshold(1e-12);
    if (cod.rank() == 0) return finish(ConstraintSolveStatus::independent_of_free, res);
    const Eigen::VectorXd u = cod.solve(g);
    // Damped step: halve until the residual decreases (guards against overshooting a sqrt).
    const std::vector<double> y0(y, y + n);
    double lambda = 1.0, trial = INFINITY;
    for (int half = 0; half < 30; ++half) {
      for (int k = 0; k < nf; ++k) y[free[k]] = y0[free[k]] - lambda * scale[static_cast<std::size_t>(free[k])] * u[k];
      trial = evaluate();
      if (trial < res) break;
      lambda *= 0.5;
    }
    ++result.iterations;
    if (!(trial < res)) {
      std::copy(y0.begin(), y0.end(), y);
      evaluate();
      if (res <= 100 * tolerance) break;  // at the noise level of the constraint
      return finish(ConstraintSolveStatus::stalled, res);
    }
    for (int k = 0; k < nf; ++k) result.correction = std::max(result.correction, std::abs(y[free[k]] - y0[free[k]]));
    res = trial;
  }
  return finish(ConstraintSolveStatus::converged, res);
}

}  // namespace nhc::runtime
