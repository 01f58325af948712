#pragma once
/// \file euler_operator.hpp
/// \brief The Euler operator E_i(F) = Σ_k (−1)^k D^k ∂F/∂q_i^(k), built two ways.
///
/// euler_operator() follows the paper (eqs. 19–21): it forms the first variation
/// δF = Σ_{i,k} ∂F/∂q_i^(k) δq_i^(k) as a linear form in the variations and removes the
/// derivatives from δq by repeated integration by parts, ∫ A D^k(δq) dt = −∫ D(A) D^{k−1}(δq) dt
/// (boundary terms vanish because δq = 0 at both ends). The coefficient left on δq_i is E_i(F).
/// euler_operator_closed_form() evaluates the closed formula directly and serves as a check.

#include <ginac/ginac.h>

#include <map>
#include <vector>

#include "nhc/expr/jet_space.hpp"
#include "nhc/expr/simplification.hpp"

namespace nhc {

/// A linear form Σ_{i,k} A_{i,k} δq_i^(k) in the variations of the coordinates.
class VariationForm {
 public:
  /// The first variation δF of F on the jet (multipliers are not varied).
  static VariationForm first_variation(const GiNaC::ex& F, const JetSpace& jet);

  /// Coefficient of δq_i^(k) (zero when absent).
  GiNaC::ex coefficient(int i, int k) const;
  void add(int i, int k, const GiNaC::ex& term);
  /// Highest k with a nonzero coefficient for coordinate i, −1 if none.
  int highest_order(int i) const;

  /// One integration by parts on the highest derivative of δq_i:
  /// A δq_i^(k) → −D(A) δq_i^(k−1). Returns false when only δq_i itself is left.
  bool integrate_by_parts_once(int i, const JetSpace& jet);

 private:
  std::map<std::pair<int, int>, GiNaC::ex> coefficients_;
};

/// E_i(F), i = 1..n, by repeated integration by parts of δF (the paper's way).
std::vector<GiNaC::ex> euler_operator(const GiNaC::ex& F, const JetSpace& jet);
/// E_i(F) by the closed formula Σ_k (−1)^k D^k ∂F/∂q_i^(k) (independent check).
std::vector<GiNaC::ex> euler_operator_closed_form(const GiNaC::ex& F, const JetSpace& jet);

}  // namespace nhc
