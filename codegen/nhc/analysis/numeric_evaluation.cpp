#include "nhc/analysis/numeric_evaluation.hpp"

#include <Eigen/SparseLU>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "nhc/errors.hpp"
#include "nhc/expr/symbol_substitution.hpp"

namespace nhc {

double evaluate_real(const GiNaC::ex& e, const GiNaC::exmap& point, const std::string& what) {
  GiNaC::ex value;
  try {
    value = substitute_symbols(e, point).evalf();
  } catch (const std::exception& error) {
    throw MathError(what + " cannot be evaluated there: " + error.what());
  }
  if (!GiNaC::is_a<GiNaC::numeric>(value)) {
    std::ostringstream s;
    s << value;
    throw MathError(what + " does not evaluate to a number there (left: " + s.str() + ")");
  }
  const GiNaC::numeric num = GiNaC::ex_to<GiNaC::numeric>(value);
  if (!num.is_real()) throw MathError(what + " is not real there");
  const double d = num.to_double();
  if (!std::isfinite(d)) throw MathError(what + " is not finite there");
  return d;
}

double condition_number(const Eigen::MatrixXd& m) {
  if (m.size() == 0) return 1.0;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(m);
  const auto& s = svd.singularValues();
  const double smax = s(0), smin = s(s.size() - 1);
  if (smax == 0.0 || smin == 0.0) return std::numeric_limits<double>::infinity();
  return smax / smin;
}

ConditionNumber condition_number(const Eigen::SparseMatrix<double>& m) {
  if (m.rows() <= kExactConditionLimit) return {condition_number(Eigen::MatrixXd(m)), false};
  return {condition_estimate_1norm(m), true};
}

double condition_estimate_1norm(const Eigen::SparseMatrix<double>& m) {
  const Eigen::Index n = m.rows();
  if (n == 0) return 1.0;
  Eigen::SparseMatrix<double> a = m;
  a.makeCompressed();
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
  lu.compute(a);
  if (lu.info() != Eigen::Success) return std::numeric_limits<double>::infinity();
  double norm_a = 0.0;  // ‖A‖₁: largest column sum
  for (Eigen::Index j = 0; j < a.outerSize(); ++j) {
    double sum = 0.0;
    for (Eigen::SparseMatrix<double>::InnerIterator it(a, j); it; ++it) sum += std::abs(it.value());
    norm_a = std::max(norm_a, sum);
  }
  if (norm_a == 0.0) return std::numeric_limits<double>::infinity();
  auto finite = [](const Eigen::VectorXd& v) { return v.allFinite(); };
  // Hager's iteration for ‖B‖₁, B = A⁻¹ (Higham 1988, Alg. 4.1): x = e/n, then repeatedly
  // y = Bx, ξ = sign(y), z = Bᵀξ and x = e_j at the largest |z_j|, until z stops growing.
  Eigen::VectorXd x = Eigen::VectorXd::Constant(n, 1.0 / static_cast<double>(n));
  double estimate = 0.0;
  Eigen::Index last = -1;
  for (int k = 0; k < 5; ++k) {
    const Eigen::VectorXd y = lu.solve(x);
    if (!finite(y)) return std::numeric_limits<double>::infinity();
    estimate = std::max(estimate, y.lpNorm<1>());
    Eigen::VectorXd xi(n);
    for (Eigen::Index i = 0; i < n; ++i) xi(i) = y(i) >= 0.0 ? 1.0 : -1.0;
    const Eigen::VectorXd z = lu.transpose().solve(xi);
    if (!finite(z)) return std::numeric_limits<double>::infinity();
    Eigen::Index j = 0;
    const double zmax = z.cwiseAbs().maxCoeff(&j);
    if (k > 0 && (zmax <= z.dot(x) || j == last)) break;
    x.setZero();
    x(j) = 1.0;
    last = j;
  }
  // Higham's extra vector x_i = (−1)^i (1 + i/(n−1)) guards against the iteration's rare
  // underestimates on matrices built to defeat it.
  Eigen::VectorXd alt(n);
  for (Eigen::Index i = 0; i < n; ++i)
    alt(i) = (i % 2 == 0 ? 1.0 : -1.0) * (1.0 + (n > 1 ? static_cast<double>(i) / static_cast<double>(n - 1) : 0.0));
  const Eigen::VectorXd w = lu.solve(alt);
  if (!finite(w)) return std::numeric_limits<double>::infinity();
  estimate = std::max(estimate, 2.0 * w.lpNorm<1>() / (3.0 * static_cast<double>(n)));
  return norm_a * estimate;
}

}  // namespace nhc
