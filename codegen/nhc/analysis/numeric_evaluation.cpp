#include "nhc/analysis/numeric_evaluation.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include "nhc/errors.hpp"

namespace nhc {

double evaluate_real(const GiNaC::ex& e, const GiNaC::exmap& point, const std::string& what) {
  GiNaC::ex value;
  try {
    value = e.subs(point, GiNaC::subs_options::no_pattern).evalf();
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

Eigen::MatrixXd evaluate_matrix(const std::vector<std::vector<GiNaC::ex>>& m,
                                const GiNaC::exmap& point, const std::string& what) {
  const auto rows = static_cast<Eigen::Index>(m.size());
  const auto cols = rows == 0 ? Eigen::Index{0} : static_cast<Eigen::Index>(m[0].size());
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(rows, cols);
  for (Eigen::Index i = 0; i < rows; ++i)
    for (Eigen::Index j = 0; j < cols; ++j) {
      const GiNaC::ex& e = m[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
      if (e.is_zero()) continue;  // structural zeros (most of a large sparse system) cost nothing
      out(i, j) = evaluate_real(e, point, what + " entry (" + std::to_string(i + 1) + "," +
                                              std::to_string(j + 1) + ")");
    }
  return out;
}

Eigen::VectorXd evaluate_vector(const std::vector<GiNaC::ex>& v, const GiNaC::exmap& point,
                                const std::string& what) {
  Eigen::VectorXd out(static_cast<Eigen::Index>(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i)
    out(static_cast<Eigen::Index>(i)) = evaluate_real(v[i], point, what);
  return out;
}

double condition_number(const Eigen::MatrixXd& m) {
  if (m.size() == 0) return 1.0;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(m);
  const auto& s = svd.singularValues();
  const double smax = s(0), smin = s(s.size() - 1);
  if (smax == 0.0 || smin == 0.0) return std::numeric_limits<double>::infinity();
  return smax / smin;
}

}  // namespace nhc
