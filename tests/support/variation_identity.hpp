#pragma once
/// \file variation_identity.hpp
/// \brief The variation identity of the paper, eq. (12), built symbolically for a generic
/// constraint f(t, q, q', …, q^(m)) (an undetermined GiNaC function) of one coordinate q.
///
/// With δq^(k) the varied derivatives (independent symbols) and D^k(δq) the derivatives of the
/// variation η = δq (a jet coordinate), the left-hand side of eq. (12) is
///   Σ_k ∂f/∂q^(k) [δq^(k) − D^k δq] + Σ_k D^k(∂f/∂q^(k) δq) − δf
///     + [∂f/∂q − Σ_k D^k ∂f/∂q^(k)] δq,      k = 1..m,
/// with δf = ∂f/∂q δq + Σ_k ∂f/∂q^(k) δq^(k). It vanishes for m = 1; for m ≥ 2 what is left
/// is the Leibniz cross terms Σ_{k=2}^m Σ_{j=1}^{k−1} C(k,j) D^{k−j}(∂f/∂q^(k)) D^j(δq).
/// Shared by the tests and the paper-check tool.

#include <ginac/ginac.h>

#include <vector>

#include "nhc/expr/jet_space.hpp"

namespace nhc::testing {

class VariationIdentity {
 public:
  /// m = 1, 2 or 3.
  explicit VariationIdentity(int m);

  int order() const { return m_; }
  const JetSpace& jet() const { return jet_; }
  /// The generic constraint f(t, q, q', …, q^(m)).
  const GiNaC::ex& constraint() const { return f_; }
  /// ∂f/∂q^(k).
  GiNaC::ex partial(int k) const;
  /// D applied to an expression of the jet (q and η = δq).
  GiNaC::ex total_derivative(const GiNaC::ex& e, int times = 1) const;
  /// D^j(δq): the j-th derivative of the variation, η^(j).
  GiNaC::ex variation_derivative(int j) const;
  /// δq^(k): the varied k-th derivative, an independent symbol.
  GiNaC::ex varied_derivative(int k) const;

  /// The left-hand side of eq. (12), expanded.
  GiNaC::ex remainder() const;
  /// Σ_{k=2}^m Σ_{j=1}^{k−1} C(k,j) D^{k−j}(∂f/∂q^(k)) D^j(δq), expanded.
  GiNaC::ex leibniz_cross_terms() const;

 private:
  int m_;
  JetSpace jet_;
  std::vector<GiNaC::symbol> varied_;
  GiNaC::ex f_;
};

}  // namespace nhc::testing
