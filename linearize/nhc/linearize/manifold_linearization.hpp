#pragma once
/// \file manifold_linearization.hpp
/// \brief The linear system on the constraint manifold in a minimal set of states
/// (docs/linearize.md, "Linearization on the constraint manifold").
///
/// From F(z, z') = 0 linearized at a stationary point, E δz' + J δz = 0 with E = ∂F/∂z',
/// J = ∂F/∂z. With z = (z_D differential, z_A algebraic), index 1 means
/// K = [E_D  J_A] is nonsingular, so δz_D' = M_D δz_D and δz_A = M_A δz_D with
/// [M_D; M_A] = −K⁻¹ J_D. The hidden constraints g(z) = 0 cut the directions
/// Ĝ δz_D = 0, Ĝ = G_D + G_A M_A. One differential state per independent row of Ĝ is
/// eliminated: candidates in order of decreasing derivative order (velocities before
/// positions, coordinates before multipliers), then decreasing column norm, each kept when it
/// raises the rank of the selected columns of Ĝ (greedy column selection with an SVD rank
/// test). With s the remaining states, δz_D = T δs and A = (M_D T)_s.
///
/// Inputs u enter as E δz' + J δz + F_u δu = 0: [δz_D'; δz_A] gains −K⁻¹ F_u δu, so with
/// N_D its differential rows, B = (N_D)_s and d(δs)/dt = A δs + B δu. Outputs
/// h(z, z', u) then read δh = C δs + D δu with δz_D = T δs, δz_A = M_A T δs + N_A δu and
/// δz_D' = M_D T δs + N_D δu (linearizer.cpp).

#include <Eigen/Dense>

#include <string>
#include <utility>
#include <vector>

namespace nhc {

struct ManifoldInput {
  Eigen::MatrixXd dF_dz, dF_dzp, dg_dz;  ///< at the point; columns over all states z
  Eigen::MatrixXd dF_du;                 ///< columns over the inputs (none: 0 columns)
  std::vector<bool> differential;        ///< per state
  std::vector<int> order;                ///< derivative order, for the elimination preference
  std::vector<bool> multiplier;
  /// Per state (may be empty): never eliminated (LinearizeOptions::states); MathError when the
  /// others cannot take every independent constraint.
  std::vector<bool> kept;
  std::vector<std::string> names;  ///< per state, for that message
};

struct ManifoldLinearization {
  std::vector<int> differential, algebraic;  ///< state indices
  /// Positions in `differential` of the kept (s) and eliminated states.
  std::vector<int> independent, dependent;
  Eigen::MatrixXd M_D, M_A, G_hat, T, A, B;
  Eigen::MatrixXd N_D, N_A;                ///< −K⁻¹ F_u: differential rows (δz_D'), algebraic rows (δz_A)
  Eigen::PartialPivLU<Eigen::MatrixXd> K;  ///< [E_D  J_A]
  double K_condition = 0.0;
  double manifold_residual = 0.0;  ///< max |Ĝ M_D T|
};

/// Throws MathError when K is singular at the point (`where` names the point).
ManifoldLinearization linearize_on_manifold(const ManifoldInput& input, double rank_tolerance = 1e-10);

/// Outputs h(z, z', u) with H = ∂h/∂z, H' = ∂h/∂z', H_u = ∂h/∂u at the point (columns over all
/// states z, and over the inputs): δh = C δs + D δu, C = (H_D + H_A M_A + H'_D M_D) T and
/// D = H_u + H_A N_A + H'_D N_D.
std::pair<Eigen::MatrixXd, Eigen::MatrixXd> output_matrices(const ManifoldLinearization& lin, const Eigen::MatrixXd& H,
                                                            const Eigen::MatrixXd& H_prime, const Eigen::MatrixXd& H_u);

}  // namespace nhc
