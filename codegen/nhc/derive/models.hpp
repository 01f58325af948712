#pragma once
/// \file models.hpp
/// \brief The four dynamical models of models.md, with exactly its residual conventions.
///
/// vakonomic  R_i = E_i(L) + E_i(λ_α f^α)                                   paper eq. (22)
/// chetaev    R_i = E_i(L) + λ_α ∂f^α/∂q_i^(m_α)                            Appell–Chetaev
/// holder     R_i = E_i(L) + Σ_α Σ_{k=1}^{m_α} [(−1)^{k+1} λ_α^(k) ∂f^α/∂q_i^(k)
///                          + ((−1)^{k+1} − 1) λ_α D^k(∂f^α/∂q_i^(k))]       paper eq. (26)
/// suslov     R_i = E_i(L) − μ_α E_i(f^α), μ_α = Σ_β ∂L/∂q'^{d_β} [A^{-1}]_{βα},
///            A_{αβ} = ∂f^α/∂q'^{d_β}                                        paper eq. (29)
/// The first three are solved together with f^α = 0; for suslov the constraints are
/// invariants to monitor. Every model adds the generalized forces Q_i of [forces] to R_i
/// (docs/forces.md): E_i(L) + Q_i = 0 is Lagrange's d/dt ∂L/∂q_i' − ∂L/∂q_i = Q_i.

#include <ginac/ginac.h>

#include <memory>
#include <string>
#include <vector>

#include "nhc/expr/jet_space.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc {

struct ReducedForm;  // nhc/derive/reduced_form.hpp

/// What a model needs from a scene: the jet, L, the constraints and the dependent coordinates.
struct MechanicalSystem {
  const JetSpace& jet;
  GiNaC::ex lagrangian;
  std::vector<GiNaC::ex> constraints;
  std::vector<int> dependent;
  std::vector<GiNaC::ex> forces = {};  ///< Q_i per coordinate; empty: none

  static MechanicalSystem of(const Scene& scene) {
    return {*scene.jet, scene.lagrangian, scene.constraints, scene.dependent, scene.forces};
  }
  /// m_α: highest derivative order of any coordinate in f^α.
  int constraint_order(int alpha) const;
};

struct DerivedModel {
  ModelKind kind = ModelKind::vakonomic;
  bool applicable = true;
  std::string reason;                     ///< why not, when !applicable
  std::vector<GiNaC::ex> equations;       ///< R_1..R_n, simplified
  std::vector<GiNaC::ex> constraints;     ///< f^1..f^g
  bool constraints_are_equations = true;  ///< false for suslov (monitored only)
  std::vector<std::string> multipliers;   ///< lambda1.. when the model has them
  /// The multiplier-free form on independent speeds, when asked for (reduce_to_independent_speeds;
  /// the printers add it): `nhc derive --form reduced`.
  std::shared_ptr<const ReducedForm> reduced;
};

DerivedModel derive_model(const MechanicalSystem& system, ModelKind kind);
/// How many times derive_model() has run in this process: the scene-level cache's tests check
/// with it that a warm build derives nothing (nhc/jit/scene_cache.hpp).
long derive_model_calls();
inline DerivedModel derive_model(const Scene& scene, ModelKind kind) {
  return refusing_at(scene.lagrangian_where,
                     "deriving the " + to_string(kind) + " model from this Lagrangian and the constraints",
                     [&] { return derive_model(MechanicalSystem::of(scene), kind); });
}

}  // namespace nhc
