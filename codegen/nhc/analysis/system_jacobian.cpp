#include "nhc/analysis/system_jacobian.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include "nhc/analysis/numeric_evaluation.hpp"
#include "nhc/expr/numeric_program.hpp"
#include "nhc/derive/euler_operator.hpp"
#include "nhc/expr/partial_derivative.hpp"
#include "nhc/base/number_text.hpp"

namespace nhc {

std::vector<JacobianEntry> system_jacobian_entries(const StructuralAnalysis& a) {
  a.require_nonsingular();
  std::vector<JacobianEntry> out;
  for (int i = 0; i < a.system.size(); ++i)
    for (const auto& e : a.sigma.row(i)) {
      if (a.d(e.col) - a.c(i) != e.value) continue;
      GiNaC::ex value =
          simplify_expression(partial_derivative(a.system.equations[static_cast<std::size_t>(i)],
                                                 a.system.jet->symbol(a.system.unknown_coordinate(e.col, e.value))));
      if (!value.is_zero()) out.push_back({i, e.col, std::move(value)});
    }
  return out;
}

std::vector<std::vector<GiNaC::ex>> system_jacobian(const StructuralAnalysis& a) {
  const auto n = static_cast<std::size_t>(a.system.size());
  std::vector<std::vector<GiNaC::ex>> jac(n, std::vector<GiNaC::ex>(n, 0));
  for (JacobianEntry& e : system_jacobian_entries(a))
    jac[static_cast<std::size_t>(e.row)][static_cast<std::size_t>(e.col)] = std::move(e.value);
  return jac;
}

namespace {

/// The entries' values at `point` through NumericProgram, the instruction list the generated
/// code runs (as the consistent initial point's Newton steps are); nothing when the point holds
/// a value that is not a real number or an entry cannot be lowered (a function without a double
/// counterpart), where GiNaC evaluates instead.
std::optional<std::vector<double>> lowered_values(const std::vector<JacobianEntry>& entries, const GiNaC::exmap& point,
                                                  const std::string& what) {
  std::vector<GiNaC::ex> inputs;
  std::vector<double> values;
  for (const auto& [symbol, value] : point) {
    if (!GiNaC::is_a<GiNaC::numeric>(value) || !GiNaC::ex_to<GiNaC::numeric>(value).is_real()) return std::nullopt;
    inputs.push_back(symbol);
    values.push_back(GiNaC::ex_to<GiNaC::numeric>(value).to_double());
  }
  NumericProgram program(inputs);
  try {
    for (const JacobianEntry& e : entries)
      program.add(e.value, what + " entry (" + std::to_string(e.row + 1) + "," + std::to_string(e.col + 1) + ")");
    program.prepare();
  } catch (const MathError&) {
    return std::nullopt;
  }
  return program.evaluate(values, what);
}

}  // namespace

Eigen::SparseMatrix<double> evaluate_system_jacobian(const std::vector<JacobianEntry>& entries, int n,
                                                     const GiNaC::exmap& point, const std::string& what) {
  const std::optional<std::vector<double>> lowered = lowered_values(entries, point, what);
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(entries.size());
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const JacobianEntry& e = entries[k];
    triplets.emplace_back(
        e.row, e.col,
        lowered ? (*lowered)[k]
                : evaluate_real(e.value, point,
                                what + " entry (" + std::to_string(e.row + 1) + "," + std::to_string(e.col + 1) + ")"));
  }
  Eigen::SparseMatrix<double> j(n, n);
  j.setFromTriplets(triplets.begin(), triplets.end());
  return j;
}

std::string describe_singular_jacobian(const StructuralAnalysis& a, const Eigen::SparseMatrix<double>& sparse,
                                       double t0) {
  if (sparse.rows() > kDescribedSingularLimit) {
    std::ostringstream s;
    const double cond = condition_number(sparse).value;
    s << "the system Jacobian of the " << to_string(a.system.model) << " model is singular at t0 = " << t0
      << " (1-norm condition estimate ";
    if (std::isfinite(cond)) s << cond;
    else s << "infinite";
    s << ", " << sparse.rows() << " unknowns: above " << kDescribedSingularLimit
      << ", the dependent equations are not named); the model cannot be integrated from this point";
    return s.str();
  }
  const Eigen::MatrixXd j(sparse);
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
  s << "the system Jacobian of the " << to_string(a.system.model)
    << " model is singular at t0 = " << base::number_text(t0, 6) << " (condition number ";
  const double cond = condition_number(j);
  if (std::isfinite(cond)) s << base::number_text(cond, 6);
  else s << "infinite";
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
