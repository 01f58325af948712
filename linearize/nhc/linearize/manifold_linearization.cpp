#include "nhc/linearize/manifold_linearization.hpp"

#include <algorithm>
#include <numeric>

#include "nhc/analysis/numeric_evaluation.hpp"
#include "nhc/errors.hpp"

namespace nhc {

namespace {

Eigen::MatrixXd columns(const Eigen::MatrixXd& m, const std::vector<int>& which) {
  Eigen::MatrixXd out(m.rows(), static_cast<Eigen::Index>(which.size()));
  for (std::size_t c = 0; c < which.size(); ++c) out.col(static_cast<Eigen::Index>(c)) = m.col(which[c]);
  return out;
}

Eigen::MatrixXd rows(const Eigen::MatrixXd& m, const std::vector<int>& which) {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(which.size()), m.cols());
  for (std::size_t r = 0; r < which.size(); ++r) out.row(static_cast<Eigen::Index>(r)) = m.row(which[r]);
  return out;
}

int numerical_rank(const Eigen::MatrixXd& m, double tolerance) {
  if (m.size() == 0) return 0;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(m);
  const Eigen::VectorXd s = svd.singularValues();
  const double threshold = tolerance * std::max(1.0, s(0));
  return static_cast<int>((s.array() > threshold).count());
}

/// Greedy choice of the eliminated columns of Ĝ (see the header).
std::vector<int> eliminated_columns(const Eigen::MatrixXd& G_hat, const ManifoldInput& in,
                                    const std::vector<int>& differential, double tolerance) {
  const int rank = numerical_rank(G_hat, tolerance);
  std::vector<int> candidates(differential.size());
  std::iota(candidates.begin(), candidates.end(), 0);
  std::stable_sort(candidates.begin(), candidates.end(), [&](int a, int b) {
    const int za = differential[static_cast<std::size_t>(a)], zb = differential[static_cast<std::size_t>(b)];
    if (in.multiplier[static_cast<std::size_t>(za)] != in.multiplier[static_cast<std::size_t>(zb)])
      return !in.multiplier[static_cast<std::size_t>(za)];
    if (in.order[static_cast<std::size_t>(za)] != in.order[static_cast<std::size_t>(zb)])
      return in.order[static_cast<std::size_t>(za)] > in.order[static_cast<std::size_t>(zb)];
    return G_hat.col(a).norm() > G_hat.col(b).norm() * (1 + 1e-12);
  });
  std::vector<int> chosen;
  for (int c : candidates) {
    if (static_cast<int>(chosen.size()) == rank) break;
    if (!in.kept.empty() && in.kept[static_cast<std::size_t>(differential[static_cast<std::size_t>(c)])]) continue;
    std::vector<int> trial = chosen;
    trial.push_back(c);
    if (numerical_rank(columns(G_hat, trial), tolerance) == static_cast<int>(trial.size())) chosen = trial;
  }
  if (static_cast<int>(chosen.size()) < rank) {
    std::string kept;
    for (std::size_t k = 0; k < in.kept.size(); ++k)
      if (in.kept[k]) kept += (kept.empty() ? "" : ", ") + in.names[k];
    throw MathError(
        "the hidden constraints fix " + std::to_string(rank) +
        " of the differential states at this point, "
        "but only " +
        std::to_string(chosen.size()) + " can be eliminated when " + kept +
        " are all kept as states: name fewer states, or others (docs/linearize.md, \"Choosing the states\")");
  }
  std::sort(chosen.begin(), chosen.end());
  return chosen;
}

}  // namespace

ManifoldLinearization linearize_on_manifold(const ManifoldInput& in, double tolerance) {
  ManifoldLinearization out;
  const auto n = static_cast<int>(in.differential.size());
  for (int k = 0; k < n; ++k)
    (in.differential[static_cast<std::size_t>(k)] ? out.differential : out.algebraic).push_back(k);
  const auto nD = static_cast<Eigen::Index>(out.differential.size());
  const auto nA = static_cast<Eigen::Index>(out.algebraic.size());

  Eigen::MatrixXd K(n, n);
  K << columns(in.dF_dzp, out.differential), columns(in.dF_dz, out.algebraic);
  out.K_condition = condition_number(K);
  if (!(out.K_condition < 1e14))
    throw MathError(
        "the index-1 matrix [dF/dz'_differential, dF/dz_algebraic] is singular at the operating point "
        "(condition number " +
        std::to_string(out.K_condition) + "): the model is not index 1 there");
  out.K.compute(K);
  const Eigen::MatrixXd M = -out.K.solve(columns(in.dF_dz, out.differential));
  out.M_D = M.topRows(nD);
  out.M_A = M.bottomRows(nA);
  out.G_hat = columns(in.dg_dz, out.differential) + columns(in.dg_dz, out.algebraic) * out.M_A;

  out.dependent = eliminated_columns(out.G_hat, in, out.differential, tolerance);
  for (int c = 0; c < static_cast<int>(nD); ++c)
    if (!std::binary_search(out.dependent.begin(), out.dependent.end(), c)) out.independent.push_back(c);

  const auto ns = static_cast<Eigen::Index>(out.independent.size());
  out.T = Eigen::MatrixXd::Zero(nD, ns);
  for (Eigen::Index c = 0; c < ns; ++c) out.T(out.independent[static_cast<std::size_t>(c)], c) = 1.0;
  if (!out.dependent.empty()) {
    // Ĝ_dep δz_dep + Ĝ_ind δs = 0 (least squares: redundant constraint rows are consistent).
    const Eigen::MatrixXd dep =
        -columns(out.G_hat, out.dependent).colPivHouseholderQr().solve(columns(out.G_hat, out.independent));
    for (std::size_t r = 0; r < out.dependent.size(); ++r)
      out.T.row(out.dependent[r]) = dep.row(static_cast<Eigen::Index>(r));
  }
  out.A = rows(out.M_D * out.T, out.independent);
  const Eigen::MatrixXd N = in.dF_du.cols() > 0 ? Eigen::MatrixXd(-out.K.solve(in.dF_du)) : Eigen::MatrixXd::Zero(n, 0);
  out.N_D = N.topRows(nD);
  out.N_A = N.bottomRows(nA);
  out.B = rows(out.N_D, out.independent).array() + 0.0;  // + 0.0: no -0 where an input does not act
  out.manifold_residual = out.G_hat.size() == 0 ? 0.0 : (out.G_hat * out.M_D * out.T).cwiseAbs().maxCoeff();
  return out;
}

std::pair<Eigen::MatrixXd, Eigen::MatrixXd> output_matrices(const ManifoldLinearization& lin, const Eigen::MatrixXd& H,
                                                            const Eigen::MatrixXd& H_prime,
                                                            const Eigen::MatrixXd& H_u) {
  const Eigen::MatrixXd H_D = columns(H, lin.differential), H_A = columns(H, lin.algebraic);
  const Eigen::MatrixXd H_prime_D = columns(H_prime, lin.differential);
  Eigen::MatrixXd C = (H_D + H_A * lin.M_A + H_prime_D * lin.M_D) * lin.T;
  Eigen::MatrixXd D = H_u + H_A * lin.N_A + H_prime_D * lin.N_D;
  return {C.array() + 0.0, D.array() + 0.0};  // + 0.0: no -0 where an output does not move
}

}  // namespace nhc
