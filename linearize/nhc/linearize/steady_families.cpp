#include "nhc/linearize/steady_families.hpp"

#include <cmath>
#include <sstream>

#include "nhc/base/number_text.hpp"

namespace nhc {

namespace {

/// Orthonormal basis of the null space of m (columns), singular values ≤ threshold.
Eigen::MatrixXd null_space(const Eigen::MatrixXd& m, double threshold) {
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(m, Eigen::ComputeFullV);
  const Eigen::VectorXd sigma = svd.singularValues();
  int rank = 0;
  for (Eigen::Index k = 0; k < sigma.size(); ++k) rank += sigma(k) > threshold ? 1 : 0;
  return svd.matrixV().rightCols(m.cols() - rank);
}

/// Part of each column of `v` orthogonal to span(basis), orthonormalized; columns that vanish
/// are dropped.
Eigen::MatrixXd new_directions(const Eigen::MatrixXd& v, const Eigen::MatrixXd& basis) {
  Eigen::MatrixXd out(v.rows(), 0);
  Eigen::MatrixXd span = basis;
  for (Eigen::Index c = 0; c < v.cols(); ++c) {
    Eigen::VectorXd x = v.col(c);
    for (int pass = 0; pass < 2; ++pass)
      for (Eigen::Index b = 0; b < span.cols(); ++b) x -= span.col(b).dot(x) * span.col(b);
    if (x.norm() < 1e-8) continue;
    x.normalize();
    out.conservativeResize(Eigen::NoChange, out.cols() + 1);
    out.col(out.cols() - 1) = x;
    span.conservativeResize(Eigen::NoChange, span.cols() + 1);
    span.col(span.cols() - 1) = x;
  }
  return out;
}

std::string combination(const Eigen::VectorXd& v, const std::vector<std::string>& states) {
  std::ostringstream text;
  const double largest = v.cwiseAbs().maxCoeff();
  bool first = true;
  for (Eigen::Index i = 0; i < v.size(); ++i) {
    if (std::abs(v(i)) < 0.1 * largest) continue;
    const double c = v(i) / largest;
    text << (first ? (c < 0 ? "-" : "") : (c < 0 ? " - " : " + "));
    if (std::abs(std::abs(c) - 1.0) > 1e-6) text << base::number_text(std::abs(c), 3) << " ";
    text << states[static_cast<std::size_t>(i)];
    first = false;
  }
  return text.str();
}

}  // namespace

std::vector<SteadyFamily> steady_families(const Eigen::MatrixXd& A, const Eigen::VectorXd& s_star,
                                          const ReducedVelocity& h, int zero_eigenvalues,
                                          const std::vector<std::string>& states, double zero_tolerance) {
  std::vector<SteadyFamily> out;
  if (A.size() == 0 || zero_eigenvalues == 0) return out;
  const double scale = std::max(1.0, A.cwiseAbs().rowwise().sum().maxCoeff());
  const double threshold = zero_tolerance * scale;
  Eigen::JacobiSVD<Eigen::MatrixXd> pseudo_inverse(A, Eigen::ComputeThinU | Eigen::ComputeThinV);
  pseudo_inverse.setThreshold(threshold / std::max(1e-300, pseudo_inverse.singularValues()(0)));
  const double epsilon = 1e-3 * (1.0 + s_star.norm());
  const double tolerance = 1e-11 * scale * (1.0 + s_star.norm());

  Eigen::MatrixXd families(A.rows(), 0);  // orthonormal basis of the family directions found
  // Continues steady motions from s* + εv; drift along `families` allowed when `relative`.
  auto continues = [&](const Eigen::VectorXd& v, bool relative) {
    const Eigen::VectorXd start = s_star + epsilon * v;
    Eigen::VectorXd s = start;
    for (int iteration = 0; iteration < 40; ++iteration) {
      std::optional<Eigen::VectorXd> velocity = h(s);
      if (!velocity || !velocity->allFinite()) return false;
      if (relative) *velocity -= families * (families.transpose() * *velocity);
      if (velocity->norm() <= tolerance) return (s - start).norm() <= 0.05 * epsilon;
      s -= pseudo_inverse.solve(*velocity);
    }
    return false;
  };
  auto add = [&](const Eigen::VectorXd& v, const std::string& description) {
    out.push_back({std::vector<double>(v.data(), v.data() + v.size()), description});
    families.conservativeResize(Eigen::NoChange, families.cols() + 1);
    families.col(families.cols() - 1) = v;
  };

  // Equilibria along kernel vectors.
  const Eigen::MatrixXd kernel = null_space(A, threshold);
  for (Eigen::Index k = 0; k < kernel.cols() && static_cast<int>(out.size()) < zero_eigenvalues; ++k)
    if (continues(kernel.col(k), false))
      add(kernel.col(k), "family of steady motions along " + combination(kernel.col(k), states));
  if (families.cols() == 0) return out;

  // Relative equilibria along Jordan chains: u with A u in the span so far.
  Eigen::MatrixXd chain = kernel;
  while (static_cast<int>(out.size()) < zero_eigenvalues) {
    Eigen::MatrixXd stacked(A.rows(), A.cols() + chain.cols());
    stacked << A, -chain;
    const Eigen::MatrixXd solutions = null_space(stacked, threshold).topRows(A.cols());
    const Eigen::MatrixXd fresh = new_directions(solutions, chain);
    if (fresh.cols() == 0) break;
    for (Eigen::Index k = 0; k < fresh.cols() && static_cast<int>(out.size()) < zero_eigenvalues; ++k) {
      if (continues(fresh.col(k), true))
        add(fresh.col(k), "family of steady motions along " + combination(fresh.col(k), states) +
                              " (relative equilibria: drifting in the family directions)");
    }
    chain.conservativeResize(Eigen::NoChange, chain.cols() + fresh.cols());
    chain.rightCols(fresh.cols()) = fresh;
  }
  return out;
}

}  // namespace nhc
