#include "nhc/analysis/system_jacobian.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "nhc/analysis/numeric_evaluation.hpp"
#include "nhc/derive/euler_operator.hpp"

namespace nhc {

std::vector<std::vector<GiNaC::ex>> system_jacobian(const StructuralAnalysis& a) {
  a.require_nonsingular();
  const int n = a.system.size();
  std::vector<std::vector<GiNaC::ex>> jac(static_cast<std::size_t>(n),
                                          std::vector<GiNaC::ex>(static_cast<std::size_t>(n), 0));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      if (!a.sigma.present(i, j) || a.d(j) - a.c(i) != a.sigma(i, j)) continue;
      jac[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] = simplify_expression(
          a.system.equations[static_cast<std::size_t>(i)].diff(
              a.system.jet->symbol(a.system.unknown_coordinate(j, a.sigma(i, j)))));
    }
  return jac;
}

std::string describe_singular_jacobian(const StructuralAnalysis& a, const Eigen::MatrixXd& j,
                                       double t0) {
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(j, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::VectorXd& sv = svd.singularValues();
  const Eigen::Index n = j.rows();
  Eigen::Index rank = 0;
  for (Eigen::Index k = 0; k < n; ++k)
    if (sv(k) > sv(0) / kSingularCondition) ++rank;
  rank = std::min(rank, n - 1);  // at least one null direction is described
  // Equations and leading derivatives that take part in some null direction (significant
  // component, above 10% of the largest, in a left or right singular vector of the null space).
  std::vector<std::string> rows, cols;
  for (Eigen::Index i = 0; i < n; ++i) {
    double left = 0.0, right = 0.0;
    for (Eigen::Index k = rank; k < n; ++k) {
      left = std::max(left, std::abs(svd.matrixU()(i, k)) / svd.matrixU().col(k).cwiseAbs().maxCoeff());
      right = std::max(right, std::abs(svd.matrixV()(i, k)) / svd.matrixV().col(k).cwiseAbs().maxCoeff());
    }
    const int m = static_cast<int>(i);
    if (left > 0.1)
      rows.push_back(derivative_equation_name(a.system.equation_names[static_cast<std::size_t>(m)], a.c(m)));
    if (right > 0.1) cols.push_back(a.system.derivative_name(m, a.d(m)));
  }
  std::ostringstream s;
  s << "the system Jacobian of the " << to_string(a.system.model) << " model is singular at t0 = "
    << t0 << " (condition number ";
  const double cond = condition_number(j);
  if (std::isfinite(cond)) s << cond; else s << "infinite";
  s << ", rank " << rank << " of " << n << "): ";
  s << (rows.size() == 1 ? "the equation " : "the equations ") << join_names(rows)
    << (rows.size() == 1 ? " does not depend on its leading derivatives there"
                         : " are linearly dependent in their leading derivatives there")
    << ", and the leading derivative" << (cols.size() == 1 ? " " : "s ") << join_names(cols)
    << (cols.size() == 1 ? " of the unknown is" : " of the unknowns are")
    << " not determined by the equations; the model cannot be integrated from this point";
  return s.str();
}

}  // namespace nhc
