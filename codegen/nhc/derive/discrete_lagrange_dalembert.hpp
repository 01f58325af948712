#pragma once
/// \file discrete_lagrange_dalembert.hpp
/// \brief The discrete Lagrange–d'Alembert equations of a scene (docs/variational.md): one step
/// of a variational integrator for the chetaev model with constraints of order 0 or 1, built from
/// the scene's own expressions (definitions stay intermediates).
///
/// Midpoint discrete Lagrangian L_d(q_a, q_b) = h L(t + h/2, (q_a + q_b)/2, (q_b − q_a)/h), forces
/// Q at the same midpoint split half to each end (Marsden & West 2001, Sect. 3.2). In the
/// position–momentum form, with m_k the discrete momentum arriving at q_k, the step from
/// (q_k, m_k) and the previous increment Δq_{k−1} = q_k − q_{k−1} solves for x = (Δq_k, λ_k),
/// Δq_k = q_{k+1} − q_k (increments, not positions: a velocity Δq/h then loses no digits to
/// q_{k+1} − q_k when a coordinate such as a wheel's angle grows large):
///
///   R_i = (m_k,i − ∂L/∂q'_i|₊)/h + ½ ∂L/∂q_i|₊ + ½ Q_i|₊ + w λ_α A^α_i(t_k, q_k, v_k) = 0,
///   C_α = f^α(t_k + h/2, (q_k + q_{k+1})/2, (q_{k+1} − q_k)/h) = 0      (order 1)
///   C_α = f^α(t_k + h, q_{k+1}) = 0                                      (order 0),
///
/// where |₊ is the midpoint of (q_k, q_{k+1}), A^α_i = ∂f^α/∂q_i^(m_α) the constraint force of
/// the chetaev model (models.md) at the node, v_k = (Δq_k + Δq_{k−1})/(2h) (A does not depend
/// on it for constraints linear in the velocities), and w = 1 (½ on the first step, whose
/// momentum is the continuous one at t0 and meets half of the node's impulse). The constraint
/// forces act at the nodes and the constraints hold on the steps: McLachlan & Perlmutter,
/// J. Nonlinear Sci. 16 (2006), eqs. (3.4)–(3.5). Then
///
///   m_{k+1,i} = ∂L/∂q'_i|₊ + (h/2)(∂L/∂q_i|₊ + Q_i|₊).
///
/// R is the discrete equation divided by h, so that it tends to the chetaev residual
/// E_i(L) + Q_i + λ_α A^α_i as h → 0 and λ_k approximates λ(t_k).

#include <ginac/ginac.h>

#include <vector>

#include "nhc/expr/stable_symbol.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc {

struct DiscreteLagrangeDAlembert {
  GiNaC::realsymbol h = stable_symbol("h"), w = stable_symbol("w");
  /// Δq_{k−1}, q_k, m_k (n each) and the unknowns x = (Δq_k, λ_k) (n + g).
  std::vector<GiNaC::realsymbol> increment_previous, q, momentum_in, x;
  /// R_1..R_n, then C_1..C_g: of t (= t_k), h, w, parameters, inputs and the symbols above.
  std::vector<GiNaC::ex> residual;
  /// m_{k+1}: of t, h, q, x.
  std::vector<GiNaC::ex> momentum_out;
  /// The continuous momentum ∂L/∂q'_i(t, q, q') in jet symbols (the first step's m_0).
  std::vector<GiNaC::ex> momentum;
};

/// The most unknowns (coordinates and multipliers) of a step: the runtime solves it with a dense
/// Newton matrix, whose LU costs (n + g)³/3 per iteration (the 1024-knife chain's 4096 would take
/// seconds per iteration and 128 MB).
inline constexpr int kMaxVariationalUnknowns = 400;

/// What the method takes, the one rule every caller checks before anything is derived:
/// InputError at the scene file for a model other than chetaev, constraints of order above 1, a
/// Lagrangian or force of order above 1 (the method needs L(t, q, q') and Q(t, q, q')), a
/// constraint holding a multiplier, or more than kMaxVariationalUnknowns unknowns per step.
void require_variational_scene(const Scene& scene, ModelKind model);

/// The step of `scene`'s `model` (require_variational_scene's refusals for any other).
DiscreteLagrangeDAlembert discrete_lagrange_dalembert(const Scene& scene, ModelKind model);

}  // namespace nhc
