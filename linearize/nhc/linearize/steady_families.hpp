#pragma once
/// \file steady_families.hpp
/// \brief Which zero eigenvalues of A come from families of steady motions (docs/linearize.md,
/// "Zero eigenvalues").
///
/// A kernel vector v of A explains a zero eigenvalue when steady motions continue along it:
/// from s* + εv, chord iterations s ← s − A⁺ h(s) on the nonlinear reduced velocity h reach
/// h = 0 within 0.05 ε of the start (a family of equilibria tangent to v; a non-family kernel
/// direction leaves an O(ε²) or O(ε³) velocity that A⁺ cannot remove).
/// A generalized kernel vector u (A u in the kernel: a Jordan chain) explains one more zero
/// eigenvalue when the same iteration reaches P h = 0, P the projector removing the family
/// directions already found: a family of relative equilibria that drift uniformly along those
/// directions (the rolling disk's steady circles drift in heading). This is how a conserved
/// quantity that is not a symmetry shows up: each of its levels carries such a steady motion.

#include <Eigen/Dense>

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "nhc/linearize/linearization.hpp"

namespace nhc {

/// h(s): the reduced velocity ds/dt at the reduced state s on the constraint manifold, or
/// nothing when the state cannot be completed there.
using ReducedVelocity = std::function<std::optional<Eigen::VectorXd>(const Eigen::VectorXd&)>;

/// Families found, at most `zero_eigenvalues` of them. `states` names the components of s.
std::vector<SteadyFamily> steady_families(const Eigen::MatrixXd& A, const Eigen::VectorXd& s_star,
                                          const ReducedVelocity& h, int zero_eigenvalues,
                                          const std::vector<std::string>& states, double zero_tolerance);

}  // namespace nhc
