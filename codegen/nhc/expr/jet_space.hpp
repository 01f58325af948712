#pragma once
/// \file jet_space.hpp
/// \brief The jet space: independent symbols q_i^(k), λ_α^(k), time t, parameters and inputs,
/// and the total derivative D on it (models.md, "Notation").
///
/// An input u (scene [inputs]) is a known signal of time: constant to every derivative but D,
/// which would need u' — not available, so D of an expression that holds an input throws the
/// InputError located at the input (models.md, "Inputs").
///
/// D = ∂_t + Σ_{i,k} q_i^(k+1) ∂/∂q_i^(k) + Σ_{α,k} λ_α^(k+1) ∂/∂λ_α^(k).
/// Jet symbols are created on demand and live as long as the JetSpace.
/// Printed names: order 0 is the variable's own name (`x`, `lambda1`), order k ≥ 1 is
/// `x_d<k>`; scene validation reserves those spellings so they cannot collide.

#include <ginac/ginac.h>

#include <map>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "nhc/errors.hpp"

namespace nhc {

enum class VariableKind { coordinate, multiplier };

/// One jet coordinate: variable `index` of `kind`, differentiated `order` times.
struct JetCoordinate {
  VariableKind kind = VariableKind::coordinate;
  int index = 0;
  int order = 0;
  bool operator<(const JetCoordinate& o) const {
    if (kind != o.kind) return kind < o.kind;
    if (index != o.index) return index < o.index;
    return order < o.order;
  }
  bool operator==(const JetCoordinate& o) const { return kind == o.kind && index == o.index && order == o.order; }
};

/// Printed name of the k-th derivative of a variable: `x`, `x_d1`, `x_d2`, …
std::string jet_symbol_name(const std::string& variable, int order);
/// LaTeX of the k-th derivative: `\dot{x}`, `\ddot{x}`, `\dddot{x}`, `x^{(4)}`; multipliers
/// `\lambda_1`, `\dot\lambda_1`.
std::string jet_symbol_latex(const std::string& variable, VariableKind kind, int order);

class JetSpace {
 public:
  JetSpace(std::vector<std::string> coordinates, int multiplier_count, std::vector<std::string> parameters,
           std::vector<std::string> inputs = {});

  int coordinate_count() const { return static_cast<int>(coordinates_.size()); }
  int multiplier_count() const { return multiplier_count_; }
  const std::vector<std::string>& coordinates() const { return coordinates_; }
  const std::vector<std::string>& parameters() const { return parameter_names_; }
  /// The index of the coordinate called `name`, if one is (a hash lookup: scenes with thousands
  /// of coordinates name them tens of thousands of times).
  std::optional<int> coordinate_index(const std::string& name) const;
  /// `lambda1`, `lambda2`, … in constraint order.
  std::string multiplier_name(int alpha) const;
  std::string variable_name(VariableKind kind, int index) const;

  const GiNaC::realsymbol& time() const { return time_; }
  const GiNaC::realsymbol& parameter(int p) const { return parameters_.at(static_cast<size_t>(p)); }
  std::optional<int> parameter_index(const std::string& name) const;

  /// The scene's inputs ([inputs]), in file order: symbols like parameters, but time-varying.
  const std::vector<std::string>& inputs() const { return input_names_; }
  const GiNaC::realsymbol& input(int k) const { return inputs_.at(static_cast<size_t>(k)); }
  std::optional<int> input_index(const std::string& name) const;
  /// The index of an input symbol, if `symbol` is one.
  std::optional<int> input_of(const GiNaC::ex& symbol) const;
  /// Where the scene defines input k: the place D's refusal to differentiate it names.
  void set_input_location(int k, SourceLocation where);

  /// q_i^(k) and λ_α^(k); created on first use. The ex shares the space's one symbol object, so
  /// a reference into it (ex_to<symbol>(q(i, k))) stays valid as long as the space.
  GiNaC::ex q(int i, int order) const { return symbol({VariableKind::coordinate, i, order}); }
  GiNaC::ex lambda(int alpha, int order) const { return symbol({VariableKind::multiplier, alpha, order}); }
  const GiNaC::realsymbol& symbol(const JetCoordinate& c) const;

  /// The jet coordinate a symbol stands for, if it is a jet symbol of this space.
  std::optional<JetCoordinate> classify(const GiNaC::ex& symbol) const;

  /// Total derivative D (models.md) and its k-th power.
  GiNaC::ex total_derivative(const GiNaC::ex& e) const;
  GiNaC::ex total_derivative(const GiNaC::ex& e, int k) const;

  /// Jet coordinates occurring in e, sorted.
  std::vector<JetCoordinate> jet_coordinates_in(const GiNaC::ex& e) const;
  /// Highest order of the variable in e, or -1 when it does not occur.
  int highest_order(const GiNaC::ex& e, VariableKind kind, int index) const;
  /// Highest order of any coordinate q_i in e, or -1.
  int highest_coordinate_order(const GiNaC::ex& e) const;

  /// Every jet symbol created so far, in creation order.
  std::vector<std::pair<JetCoordinate, GiNaC::realsymbol>> symbols() const;

 private:
  std::vector<std::string> coordinates_;
  std::unordered_map<std::string, int> coordinate_indices_, parameter_indices_, input_indices_;
  int multiplier_count_;
  std::vector<std::string> parameter_names_;
  GiNaC::realsymbol time_;
  std::vector<GiNaC::realsymbol> parameters_;
  std::vector<std::string> input_names_;
  std::vector<GiNaC::realsymbol> inputs_;
  std::vector<SourceLocation> input_locations_;
  /// Each jet symbol once, on the heap (symbol()): q() and lambda() share it, never copy it.
  mutable std::map<JetCoordinate, GiNaC::ex> jet_;
  mutable std::map<GiNaC::ex, JetCoordinate, GiNaC::ex_is_less> by_symbol_;
  mutable std::vector<JetCoordinate> creation_order_;
};

}  // namespace nhc
