#pragma once
/// \file structural_analysis.hpp
/// \brief Pryce's Σ-method on a DAE (models.md, "Structural analysis", steps 1–4): signature
/// matrix, highest-value transversal, canonical offsets, structural index, degrees of freedom,
/// the initial values a user must give and the hidden constraints that tie them together.
/// References: Pryce, BIT 41 (2001) 364–394; Nedialkov & Pryce, BIT 45 (2005), 47 (2007).

#include <string>
#include <vector>

#include "nhc/analysis/dae_system.hpp"
#include "nhc/analysis/offsets.hpp"
#include "nhc/analysis/signature_matrix.hpp"
#include "nhc/analysis/transversal.hpp"

namespace nhc {

/// D^order f_equation = 0 with order < c_equation: holds along every solution, involves only
/// the x_j^(k) with k < d_j, and so restricts the initial values.
struct HiddenConstraint {
  int equation = 0;
  int order = 0;
  std::string name;  ///< "f1", "D f1", "D^2 f1"
};

struct StructuralAnalysis {
  DaeSystem system;
  SignatureMatrix sigma;
  /// Column j of each unknown by (kind, index) (unknown_columns), filled by analyze_structure.
  std::map<std::pair<VariableKind, int>, int> column_of_unknown;

  /// No transversal of finite entries: the remaining fields below sigma are empty.
  bool structurally_singular = false;
  StructuralDeficiency deficiency;
  std::string singular_reason;  ///< in words: which equations, which unknowns

  Transversal transversal;
  Offsets offsets;
  /// ν = max c_i, plus 1 when some d_j = 0 (an algebraic unknown).
  int index = 0;
  /// Σ d_j − Σ c_i.
  int dof = 0;
  /// x_j^(k), k < d_j, in unknown order then derivative order.
  std::vector<JetCoordinate> initial_values_needed;
  std::vector<HiddenConstraint> hidden_constraints;

  int c(int i) const { return offsets.c.at(static_cast<std::size_t>(i)); }
  int d(int j) const { return offsets.d.at(static_cast<std::size_t>(j)); }
  /// Throws MathError with singular_reason when structurally singular.
  void require_nonsingular() const;
};

/// Runs steps 1–3 and derives index, dof, needed initial values and hidden constraints.
/// Does not throw for structurally singular systems: it fills singular_reason instead.
StructuralAnalysis analyze_structure(DaeSystem system);
/// How many times analyze_structure() has run in this process: the tests of app::Preparation
/// check with it that a simulate runs the Σ-method once.
long analyze_structure_calls();

/// D^r f_i, simplified (simplify_expression), in the x_j^(k) with k ≤ d_j + r − c_i. Jet
/// symbols of higher order, which can occur only with identically vanishing coefficients,
/// are removed. Requires a structurally nonsingular analysis.
GiNaC::ex differentiated_equation(const StructuralAnalysis& analysis, int i, int r);

/// "x, y and lambda1".
std::string join_names(const std::vector<std::string>& names);

}  // namespace nhc
