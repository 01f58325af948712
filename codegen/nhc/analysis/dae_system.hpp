#pragma once
/// \file dae_system.hpp
/// \brief A derived model seen as a square DAE for structural analysis (models.md,
/// "Structural analysis"): unknowns x_j = (q_1..q_n, λ_1..λ_g) and equations
/// f_i = (R_1..R_n, f^1..f^g); for suslov the unknowns are q only and the equations R only.

#include <ginac/ginac.h>

#include <memory>
#include <string>
#include <vector>

#include "nhc/expr/jet_space.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc {

/// One unknown x_j of the DAE: a coordinate or a multiplier.
struct Unknown {
  VariableKind kind = VariableKind::coordinate;
  int index = 0;
  std::string name;  ///< "x", "lambda1"
};

struct DaeSystem {
  ModelKind model = ModelKind::vakonomic;
  std::shared_ptr<JetSpace> jet;
  std::vector<Unknown> unknowns;
  std::vector<GiNaC::ex> equations;
  std::vector<std::string> equation_names;  ///< "R_x", …, "f1", …
  /// suslov: the constraints f^α, not equations of the DAE but invariants of its motion;
  /// consistent initial values must satisfy them.
  std::vector<GiNaC::ex> monitored_constraints;
  std::vector<std::string> monitored_constraint_names;

  int size() const { return static_cast<int>(equations.size()); }
  /// The jet symbol x_j^(order).
  GiNaC::ex unknown_symbol(int j, int order) const;
  JetCoordinate unknown_coordinate(int j, int order) const;
  /// "x", "x'", "x''", "x'''", "x^(4)", "lambda1'".
  std::string derivative_name(int j, int order) const;
};

/// "x", "x'", …: primes up to the third derivative, "^(k)" above.
std::string prime_name(const std::string& variable, int order);

/// Name of D^r applied to an equation: "f1", "D f1", "D^2 f1".
std::string derivative_equation_name(const std::string& equation, int order);

/// The DAE of a derived model. Throws MathError when the model is not applicable to the scene.
DaeSystem dae_system_of(const Scene& scene, const DerivedModel& model);

}  // namespace nhc
