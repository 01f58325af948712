#pragma once
/// \file intermediate.hpp
/// \brief Named intermediate quantities (docs/intermediates.md): a definition d := e that stays a symbol,
/// with its expression attached, instead of being substituted into everything that uses it.
/// GiNaC's `diff` applies the chain rule through it, each ∂d/∂z and D d memoized in d; GiNaC's
/// own tree functions (has, subs, expand, preorder iteration) see an independent symbol, so code
/// that asks what an expression depends on uses symbols_through(), and code that needs the
/// substituted form expand_intermediates(). Design and measurements: docs/intermediates.md.

#include <ginac/ginac.h>

#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "nhc/expr/symbolic_policy.hpp"

namespace nhc {

/// e with its intermediates substituted when that form is small (kSubstituteIntoExpressionBelowNodes,
/// kSimplifyIntermediateMaxTerms: symbolic_policy.hpp), else e.
GiNaC::ex substituted_where_small(const GiNaC::ex& e);

/// e simplified under the same policy, or e itself when that is not shorter.
GiNaC::ex simplified_where_it_pays(const GiNaC::ex& e);

/// The size of e as a tree of GiNaC nodes, counted up to `limit` (cheap on large e).
int expression_nodes(const GiNaC::ex& e, int limit = kInlineBelowNodes);
/// The same for e with its intermediates substituted, without substituting (each
/// intermediate's substituted size is counted once and remembered, up to `limit`).
int expanded_nodes(const GiNaC::ex& e, int limit);

class Intermediate : public GiNaC::realsymbol {
 public:
  /// What an intermediate stands for: a quantity the scene defines, or a partial or total
  /// derivative of one (named after it: `dT_dphi`, `T_dot`; LaTeX ∂_φ T, \dot T).
  enum class Origin { defined, derivative };

  /// d := expression, printed as `name` (LaTeX `latex`).
  Intermediate(const std::string& name, const std::string& latex, const GiNaC::ex& expression,
               Origin origin = Origin::defined);

  const GiNaC::ex& expression() const { return definition_->expression; }
  const std::string& intermediate_name() const { return definition_->name; }
  const std::string& latex_name() const { return definition_->latex; }
  Origin origin() const { return definition_->origin; }
  /// expanded_nodes(expression(), limit), remembered.
  int expanded_size(int limit) const;
  /// The intermediates `expression()` names directly.
  const std::vector<GiNaC::ex>& uses() const;
  /// The symbols d depends on that are not intermediates, through the ones it uses; memoized.
  const std::set<GiNaC::ex, GiNaC::ex_is_less>& free_symbols() const;
  /// D d, computed once: an intermediate `name_dot` unless small. An intermediate belongs to one
  /// jet space, so one D serves it.
  GiNaC::ex total_derivative(const class TotalDerivative& D) const;

  Intermediate* duplicate() const override {
    auto* copy = new Intermediate(*this);
    copy->setflag(GiNaC::status_flags::dynallocated);
    return copy;
  }

 protected:
  /// stable_symbol_hash(serial): the same in every build (stable_symbol.hpp says why).
  unsigned calchash() const override;
  /// ∂d/∂s by the chain rule through the expression, memoized; 1 for d itself. Under
  /// ExplicitDerivatives, 0 for every other symbol.
  GiNaC::ex derivative(const GiNaC::symbol& s) const override;

 private:
  struct Definition {
    std::string name, latex;
    GiNaC::ex expression;
    Origin origin = Origin::defined;
    mutable std::unique_ptr<std::vector<GiNaC::ex>> uses;                ///< direct intermediates, on demand
    mutable std::map<GiNaC::ex, GiNaC::ex, GiNaC::ex_is_less> partials;  ///< ∂d/∂s by s
    mutable std::unique_ptr<GiNaC::ex> total;                            ///< D d, on demand
    mutable int expanded_nodes = -1, expanded_limit = 0;                 ///< expanded_nodes(expression), up to a limit
    /// Every non-intermediate symbol d depends on, through the intermediates it uses.
    mutable std::unique_ptr<std::set<GiNaC::ex, GiNaC::ex_is_less>> free_symbols;
  };
  std::shared_ptr<Definition> definition_;
};

/// Whether e is an Intermediate.
bool is_intermediate(const GiNaC::ex& e);

/// While alive, on this thread, an intermediate's derivative with respect to any symbol but
/// itself is 0: `e.diff(z)` is then the explicit partial ∂e/∂z|_explicit that treats the
/// intermediates as independent (needed to write D e without counting a chain twice).
class ExplicitDerivatives {
 public:
  ExplicitDerivatives();
  ~ExplicitDerivatives();
  ExplicitDerivatives(const ExplicitDerivatives&) = delete;
  ExplicitDerivatives& operator=(const ExplicitDerivatives&) = delete;

 private:
  bool previous_;
};

/// The intermediates e names directly (not through other intermediates), each once, in the
/// order found.
std::vector<GiNaC::ex> direct_intermediates(const GiNaC::ex& e);

/// Every intermediate e depends on, directly or through others, in dependency order (each after
/// the intermediates its expression uses): the order in which code computes them. Iterative.
std::vector<GiNaC::ex> intermediates_in_order(const std::vector<GiNaC::ex>& expressions);

/// The symbols (jet variables, t, parameters) e depends on, through its intermediates; not the
/// intermediates themselves. Memoized per intermediate.
std::set<GiNaC::ex, GiNaC::ex_is_less> symbols_through(const GiNaC::ex& e);

/// Whether e depends on `symbol`, through its intermediates (GiNaC's has() stops at them).
bool depends_on(const GiNaC::ex& e, const GiNaC::ex& symbol);

/// e with every intermediate replaced by its expression, recursively: the fully substituted
/// form. Each intermediate is expanded once (dependency order, no recursion on chain length).
GiNaC::ex expand_intermediates(const GiNaC::ex& e);

/// The total derivative D on expressions over intermediates, given D of the plain symbols:
///
///     D e = Σ_{z in e} ∂e/∂z|_explicit · D z + Σ_{d in e} ∂e/∂d|_explicit · D d,
///
/// where the first sum runs over e's own symbols that are not intermediates and D d is computed
/// once per intermediate (an intermediate itself unless small). `of_symbol(z)` gives D z: 1 for
/// t, 0 for a parameter, q^(k+1) for q^(k).
class TotalDerivative {
 public:
  using OfSymbol = std::function<GiNaC::ex(const GiNaC::ex& symbol)>;
  explicit TotalDerivative(OfSymbol of_symbol) : of_symbol_(std::move(of_symbol)) {}
  GiNaC::ex operator()(const GiNaC::ex& e) const;
  GiNaC::ex of_symbol(const GiNaC::ex& s) const { return of_symbol_(s); }

 private:
  OfSymbol of_symbol_;
};

}  // namespace nhc
