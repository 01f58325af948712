#pragma once
/// \file index1_system.hpp
/// \brief The index-1 form of a model (models.md, "Structural analysis", step 5): what code
/// generation and the runtime consume.
///
/// Unknowns x_j (q_1..q_n, then λ_1..λ_g; suslov: q only) with Pryce offsets d_j; equations f_i
/// (R_1..R_n, then f^1..f^g; suslov: R only) with offsets c_i.
/// States y: for each unknown x_j in order, x_j, x_j', …, x_j^(d_j−1) (differential), or x_j alone
/// (algebraic) when d_j = 0. Residuals F(t, y, y') = 0, in this order:
///   1. for each equation f_i in order: D^{c_i} f_i, with x_j^(k) written as y[state(x_j, k)] for
///      k < d_j and x_j^(d_j) as yp[state(x_j, d_j − 1)];
///   2. for each unknown x_j with d_j ≥ 2, for k = 0..d_j−2: yp[state(x_j,k)] − y[state(x_j,k+1)].
/// Hidden constraints: D^r f_i for r < c_i, in (t, p, y) only; suslov: its monitored constraints
/// f^α that involve initial data only (Suslov's equations keep them, so the motion must start on
/// them), as initial_value_constraints() lists them.

#include <ginac/ginac.h>

#include <memory>

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "nhc/expr/jet_space.hpp"
#include "nhc/expr/symbol_substitution.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc {

/// One component of the state vector y: the order-th derivative of an unknown.
struct StateComponent {
  VariableKind kind = VariableKind::coordinate;
  int index = 0;             ///< coordinate or multiplier index
  int order = 0;             ///< derivative order held in y
  bool differential = true;  ///< IDA id: true when its derivative appears (d_j ≥ 1)
  std::string name;          ///< "x", "x'", "x''", "lambda1", "lambda1'"
};

struct Index1System {
  ModelKind model = ModelKind::chetaev;
  std::shared_ptr<JetSpace> jet;

  std::vector<StateComponent> states;
  /// Symbols standing for y_k and y'_k in the expressions below (printed "y[k]", "yp[k]").
  std::vector<GiNaC::realsymbol> y, yp;
  /// F(t, p, y, y') = 0; as many as states.
  std::vector<GiNaC::ex> residuals;
  /// Short description of each residual, e.g. "D^1 f1", "R_x", "chain x' = x'".
  std::vector<std::string> residual_names;
  /// Hidden constraints g(t, p, y) = 0 (D^r f_i, r < c_i; suslov: f^α), e.g. named "f1", "D f1".
  std::vector<GiNaC::ex> hidden_constraints;
  std::vector<std::string> hidden_constraint_names;

  /// ∂g/∂y of each hidden constraint, by rows: the pairs (k, ∂g_r/∂y_k) of the states that
  /// occur in g_r, by increasing k; the others are 0. Sparse because a chain of N bodies has N
  /// hidden constraints in 7N states, each involving a few.
  std::vector<std::vector<std::pair<int, GiNaC::ex>>> hidden_constraint_jacobian;
  /// ∂g_r/∂y_k (0 when y_k does not occur in g_r).
  GiNaC::ex hidden_constraint_derivative(std::size_t r, int k) const {
    for (const auto& [state, value] : hidden_constraint_jacobian.at(r))
      if (state == k) return value;
    return 0;
  }
  /// Pryce offsets: c per equation (R_1..R_n, f^1..f^g), d per unknown (q, then λ).
  std::vector<int> c, d;

  int size() const { return static_cast<int>(states.size()); }
  /// Maps a jet symbol x^(k) with k ≤ d_j to its y / yp symbol (to rewrite scene expressions
  /// such as invariants in state variables). Filled by the reduction.
  GiNaC::exmap jet_to_state;
  /// e rewritten in states by jet_to_state, through named intermediates: each intermediate gets
  /// one image for the whole system (symbol_substitution.hpp), shared by residuals, hidden
  /// constraints and invariants alike.
  GiNaC::ex in_states(const GiNaC::ex& e) const {
    // Made on first use, when the reduction has filled jet_to_state.
    if (!state_substitution_) state_substitution_ = std::make_shared<SymbolSubstitution>(jet_to_state);
    return (*state_substitution_)(e);
  }

 private:
  mutable std::shared_ptr<SymbolSubstitution> state_substitution_;
};

}  // namespace nhc
