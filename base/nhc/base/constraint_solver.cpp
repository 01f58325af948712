#include "nhc/base/constraint_solver.hpp"

#include <Eigen/Dense>
#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>

#include <algorithm>
#include <cmath>
#include <optional>

namespace nhc::base {

namespace {

/// The minimum-norm u with A u = g for A = G D restricted to the free columns, from the
/// sparse entries of G: u = Aᵀ (A Aᵀ)⁻¹ g. nullopt when A A^T is (numerically) singular.
std::optional<Eigen::VectorXd> sparse_minimum_norm_step(const std::vector<SparseEntry>& entries, int m,
                                                        const std::vector<int>& free_index,
                                                        const std::vector<double>& scale, int nf,
                                                        const Eigen::VectorXd& g) {
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(entries.size());
  for (const SparseEntry& e : entries) {
    const int k = free_index[static_cast<std::size_t>(e.col)];
    if (k >= 0 && e.value != 0.0) triplets.emplace_back(e.row, k, e.value * scale[static_cast<std::size_t>(e.col)]);
  }
  Eigen::SparseMatrix<double> a(m, nf);
  a.setFromTriplets(triplets.begin(), triplets.end());
  const Eigen::SparseMatrix<double> normal = a * a.transpose();
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(normal);
  if (ldlt.info() != Eigen::Success) return std::nullopt;
  const Eigen::VectorXd d = ldlt.vectorD();
  const double largest = d.cwiseAbs().maxCoeff();
  if (!(largest > 0.0) || (d.array() <= 1e-12 * largest).any()) return std::nullopt;
  const Eigen::VectorXd u = a.transpose() * ldlt.solve(g);
  if (!u.allFinite()) return std::nullopt;
  return u;
}

}  // namespace

ConstraintSolveResult solve_constraints(const ConstraintFunctions& functions, double* y,
                                        const std::vector<double>& scale, double tolerance, int max_iterations) {
  ConstraintSolveResult result;
  const int m = functions.count, n = functions.size;
  if (m == 0) return result;

  std::vector<int> free;
  for (int i = 0; i < n; ++i)
    if (scale[static_cast<std::size_t>(i)] > 0) free.push_back(i);
  const int nf = static_cast<int>(free.size());

  std::vector<int> free_index(static_cast<std::size_t>(n), -1);  // column of y_i among the free values
  for (int k = 0; k < nf; ++k) free_index[static_cast<std::size_t>(free[static_cast<std::size_t>(k)])] = k;
  std::vector<SparseEntry> entries;

  Eigen::VectorXd g(m);
  Eigen::MatrixXd G;
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
    std::optional<Eigen::VectorXd> sparse_step;
    if (functions.sparse_jacobian && static_cast<long long>(m) * nf > kSparseStepSize) {
      entries.clear();
      functions.sparse_jacobian(y, entries);
      for (const SparseEntry& e : entries)
        if (!std::isfinite(e.value)) return finish(ConstraintSolveStatus::gradient_not_finite, res);
      sparse_step = sparse_minimum_norm_step(entries, m, free_index, scale, nf, g);
    }
    Eigen::VectorXd u;
    if (sparse_step) {
      u = std::move(*sparse_step);
    } else {
      if (G.size() == 0) G.resize(m, n);  // allocated only when the dense step is taken
      functions.jacobian(y, G.data());
      if (!G.allFinite()) return finish(ConstraintSolveStatus::gradient_not_finite, res);
      Eigen::MatrixXd A(m, nf);
      for (int k = 0; k < nf; ++k) A.col(k) = G.col(free[k]) * scale[static_cast<std::size_t>(free[k])];
      Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(A);
      cod.setThreshold(1e-12);
      if (cod.rank() == 0) return finish(ConstraintSolveStatus::independent_of_free, res);
      u = cod.solve(g);
    }
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

}  // namespace nhc::base
