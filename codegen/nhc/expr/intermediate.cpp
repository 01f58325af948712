#include "nhc/expr/intermediate.hpp"

#include <algorithm>
#include <atomic>
#include <unordered_map>
#include <unordered_set>

#include "nhc/expr/partial_derivative.hpp"
#include "nhc/expr/simplification.hpp"
#include "nhc/expr/stable_symbol.hpp"
#include "nhc/expr/traversal.hpp"
#include "nhc/expr/work_budget.hpp"

namespace nhc {

namespace {

thread_local bool explicit_derivatives = false;

/// Whether any intermediate has been made in this process: until one has, no expression can hold
/// one, and the searches below return at once (scenes whose definitions are substituted pay
/// nothing for them).
std::atomic<bool> any_intermediate{false};

using ExSet = std::set<GiNaC::ex, GiNaC::ex_is_less>;

/// Calls `found` on each distinct intermediate met in e; does not descend into intermediates'
/// expressions.
template <class Found>
void each_intermediate(const GiNaC::ex& e, Found found) {
  visit_distinct(e, [&](const GiNaC::ex& x) {
    if (!is_intermediate(x)) return true;
    found(x);
    return false;
  });
}

/// e's own symbols that are not intermediates (not through them).
ExSet own_symbols(const GiNaC::ex& e) {
  ExSet out;
  visit_distinct(e, [&](const GiNaC::ex& x) {
    if (is_intermediate(x)) return false;
    if (GiNaC::is_a<GiNaC::symbol>(x)) out.insert(x);
    return true;
  });
  return out;
}

/// A derived quantity of `d` (a partial or D d): kept as an expression when small, else an
/// intermediate named `name`.
GiNaC::ex keep_or_name(const GiNaC::ex& value, const std::string& name, const std::string& latex) {
  if (expression_nodes(value) < kInlineBelowNodes) return value;
  return Intermediate(name, latex, value, Intermediate::Origin::derivative);
}

const Intermediate& as_intermediate(const GiNaC::ex& e) { return GiNaC::ex_to<Intermediate>(e); }

/// How s prints in LaTeX (`\dot{x}` for x'), for the names of derivatives.
std::string latex_of(const GiNaC::symbol& s) {
  const std::string tex = s.get_TeX_name();
  return tex.empty() ? s.get_name() : tex;
}

/// ∂X/∂s as a textbook writes it: \frac{\partial T}{\partial \dot{\psi}}.
std::string partial_latex(const std::string& of, const std::string& by) {
  return "\\frac{\\partial " + of + "}{\\partial " + by + "}";
}

/// dX/dt: a dot over a plain name (\dot{T}), d/dt before anything else, so that the dot is never
/// lost over a fraction or a subscript (\frac{d}{dt}\frac{\partial T}{\partial \dot{\psi}}).
std::string time_derivative_latex(const std::string& of) {
  const bool plain = of.find_first_of("\\{}_^ ") == std::string::npos;
  return plain ? "\\dot{" + of + "}" : "\\frac{d}{dt}" + of;
}

}  // namespace

int expression_nodes(const GiNaC::ex& e, int limit) {
  int count = 0;
  std::vector<GiNaC::ex> stack{e};
  while (!stack.empty() && count < limit) {
    const GiNaC::ex x = stack.back();
    stack.pop_back();
    ++count;
    for (std::size_t k = 0; k < x.nops(); ++k) stack.push_back(x.op(k));
  }
  return count;
}

int expanded_nodes(const GiNaC::ex& e, int limit) {
  int count = 0;
  std::vector<GiNaC::ex> stack{e};
  while (!stack.empty() && count < limit) {
    const GiNaC::ex x = stack.back();
    stack.pop_back();
    if (is_intermediate(x)) {
      count += GiNaC::ex_to<Intermediate>(x).expanded_size(limit);
      continue;
    }
    ++count;
    for (std::size_t k = 0; k < x.nops(); ++k) stack.push_back(x.op(k));
  }
  return std::min(count, limit);
}

int Intermediate::expanded_size(int limit) const {
  Definition& d = *definition_;
  // A size counted under a smaller limit that reached it is only a lower bound.
  if (d.expanded_nodes < 0 || (d.expanded_nodes >= d.expanded_limit && limit > d.expanded_limit)) {
    d.expanded_nodes = expanded_nodes(d.expression, limit);
    d.expanded_limit = limit;
  }
  return std::min(d.expanded_nodes, limit);
}

bool is_intermediate(const GiNaC::ex& e) {
  // A virtual flag test first: a dynamic_cast that fails compares type names with strcmp, and
  // the traversals ask this of every node.
  return e.info(GiNaC::info_flags::symbol) && GiNaC::is_a<Intermediate>(e);
}

GiNaC::ex substituted_where_small(const GiNaC::ex& e) {
  if (direct_intermediates(e).empty()) return e;
  if (expanded_nodes(e, kSubstituteIntoExpressionBelowNodes) >= kSubstituteIntoExpressionBelowNodes) return e;
  // Small as a tree can still be large expanded: ((x' + y + 1)^2 + x)^2 + … (a chain of squares).
  GiNaC::ex substituted = expand_intermediates(e);
  if (work_budget::expanded_terms(substituted) > kSimplifyIntermediateMaxTerms) return e;
  return substituted;
}

GiNaC::ex simplified_where_it_pays(const GiNaC::ex& e) {
  if (GiNaC::is_a<GiNaC::symbol>(e) || GiNaC::is_a<GiNaC::numeric>(e)) return e;
  if (work_budget::expanded_terms(e) > kSimplifyIntermediateMaxTerms) return e;
  GiNaC::ex simplified = simplify_expression(e);
  return work_budget::node_count(simplified) < work_budget::node_count(e) ? simplified : e;
}

Intermediate::Intermediate(const std::string& name, const std::string& latex, const GiNaC::ex& expression,
                           Origin origin)
    : GiNaC::realsymbol(name, latex), definition_(std::make_shared<Definition>()) {
  definition_->origin = origin;
  any_intermediate.store(true, std::memory_order_relaxed);
  definition_->name = name;
  definition_->latex = latex;
  definition_->expression = expression;
}

unsigned Intermediate::calchash() const {
  hashvalue = stable_symbol_hash(get_name());
  setflag(GiNaC::status_flags::hash_calculated);
  return hashvalue;
}

const std::vector<GiNaC::ex>& Intermediate::uses() const {
  if (!definition_->uses) {
    auto uses = std::make_unique<std::vector<GiNaC::ex>>(direct_intermediates(definition_->expression));
    definition_->uses = std::move(uses);
  }
  return *definition_->uses;
}

const ExSet& Intermediate::free_symbols() const {
  if (definition_->free_symbols) return *definition_->free_symbols;
  // Dependencies first, so that each intermediate's set is built from finished ones.
  for (const GiNaC::ex& d : intermediates_in_order({*this})) {
    const Intermediate& i = as_intermediate(d);
    if (i.definition_->free_symbols) continue;
    auto symbols = std::make_unique<ExSet>(own_symbols(i.expression()));
    for (const GiNaC::ex& used : i.uses()) {
      const ExSet& theirs = *as_intermediate(used).definition_->free_symbols;
      symbols->insert(theirs.begin(), theirs.end());
    }
    i.definition_->free_symbols = std::move(symbols);
  }
  return *definition_->free_symbols;
}

GiNaC::ex Intermediate::derivative(const GiNaC::symbol& s) const {
  if (is_equal(s)) return 1;
  if (explicit_derivatives) return 0;
  const GiNaC::ex key = s;
  if (const auto it = definition_->partials.find(key); it != definition_->partials.end()) return it->second;
  // Through a symbol d does not depend on, nothing: no expression is differentiated. With respect
  // to a jet variable the memoized free symbols answer; with respect to an intermediate, a search.
  const bool through_intermediate = is_intermediate(key);
  const auto depends = [&](const Intermediate& i) {
    if (!through_intermediate) return i.free_symbols().count(key) > 0;
    const std::vector<GiNaC::ex> order = intermediates_in_order({i});
    return std::any_of(order.begin(), order.end(), [&](const GiNaC::ex& u) { return u.is_equal(key); });
  };
  // The partials of the intermediates d uses come first, in dependency order, so that the chain
  // rule finds them memoized instead of recursing once per link of a chain. Only the ones not yet
  // memoized are visited (depth-first post-order, explicit stack).
  std::vector<std::pair<const Intermediate*, std::size_t>> stack{{this, 0}};
  std::unordered_set<const Definition*> visited{definition_.get()};
  while (!stack.empty()) {
    auto& [i, next] = stack.back();
    Definition& di = *i->definition_;
    if (next == 0 && !depends(*i)) {
      di.partials.emplace(key, 0);
      stack.pop_back();
      continue;
    }
    const std::vector<GiNaC::ex>& uses = i->uses();
    if (next < uses.size()) {
      const Intermediate& u = as_intermediate(uses[next++]);
      if (!u.is_equal(s) && !u.definition_->partials.count(key) && visited.insert(u.definition_.get()).second)
        stack.emplace_back(&u, 0);
      continue;
    }
    di.partials.emplace(key, keep_or_name(partial_derivative(di.expression, s), "d" + di.name + "_d" + s.get_name(),
                                          partial_latex(di.latex, latex_of(s))));
    stack.pop_back();
  }
  return definition_->partials.at(key);
}

GiNaC::ex Intermediate::total_derivative(const TotalDerivative& D) const {
  if (definition_->total) return *definition_->total;
  // Dependencies first: D of each used intermediate is memoized before it is needed.
  for (const GiNaC::ex& d : intermediates_in_order({*this})) {
    const Intermediate& i = as_intermediate(d);
    if (i.definition_->total) continue;
    const GiNaC::ex value = D(i.expression());
    i.definition_->total = std::make_unique<GiNaC::ex>(
        keep_or_name(value, i.definition_->name + "_dot", time_derivative_latex(i.definition_->latex)));
  }
  return *definition_->total;
}

ExplicitDerivatives::ExplicitDerivatives() : previous_(explicit_derivatives) { explicit_derivatives = true; }
ExplicitDerivatives::~ExplicitDerivatives() { explicit_derivatives = previous_; }

std::vector<GiNaC::ex> direct_intermediates(const GiNaC::ex& e) {
  std::vector<GiNaC::ex> out;
  if (!any_intermediate.load(std::memory_order_relaxed)) return out;
  each_intermediate(e, [&](const GiNaC::ex& d) { out.push_back(d); });  // each distinct one once
  return out;
}

std::vector<GiNaC::ex> intermediates_in_order(const std::vector<GiNaC::ex>& expressions) {
  // Depth-first post-order with an explicit stack: an intermediate is emitted after all it uses.
  std::vector<GiNaC::ex> order;
  if (!any_intermediate.load(std::memory_order_relaxed)) return order;
  ExSet done, on_stack;
  for (const GiNaC::ex& root : expressions) {
    std::vector<std::pair<GiNaC::ex, std::size_t>> stack;
    const std::vector<GiNaC::ex> roots =
        is_intermediate(root) ? std::vector<GiNaC::ex>{root} : direct_intermediates(root);
    for (const GiNaC::ex& r : roots) {
      if (done.count(r)) continue;
      stack.emplace_back(r, 0);
      on_stack.insert(r);
      while (!stack.empty()) {
        auto& [d, next] = stack.back();
        const std::vector<GiNaC::ex>& uses = as_intermediate(d).uses();
        if (next < uses.size()) {
          const GiNaC::ex u = uses[next++];
          if (!done.count(u) && on_stack.insert(u).second) stack.emplace_back(u, 0);
          continue;
        }
        done.insert(d);
        on_stack.erase(d);
        order.push_back(d);
        stack.pop_back();
      }
    }
  }
  return order;
}

std::set<GiNaC::ex, GiNaC::ex_is_less> symbols_through(const GiNaC::ex& e) {
  ExSet out = own_symbols(e);
  for (const GiNaC::ex& d : direct_intermediates(e)) {
    const ExSet& theirs = as_intermediate(d).free_symbols();
    out.insert(theirs.begin(), theirs.end());
  }
  return out;
}

bool depends_on(const GiNaC::ex& e, const GiNaC::ex& symbol) {
  if (e.has(symbol)) return true;
  for (const GiNaC::ex& d : direct_intermediates(e))
    if (GiNaC::ex_to<Intermediate>(d).free_symbols().count(symbol)) return true;
  return false;
}

GiNaC::ex expand_intermediates(const GiNaC::ex& e) {
  GiNaC::exmap expanded;  // intermediate → its fully substituted expression
  for (const GiNaC::ex& d : intermediates_in_order({e})) {
    const Intermediate& i = as_intermediate(d);
    GiNaC::exmap direct;
    for (const GiNaC::ex& u : i.uses()) direct[u] = expanded.at(u);
    expanded[d] = direct.empty() ? i.expression() : i.expression().subs(direct, GiNaC::subs_options::no_pattern);
  }
  if (is_intermediate(e)) return expanded.at(e);
  GiNaC::exmap direct;
  for (const GiNaC::ex& u : direct_intermediates(e)) direct[u] = expanded.at(u);
  return direct.empty() ? e : e.subs(direct, GiNaC::subs_options::no_pattern);
}

GiNaC::ex TotalDerivative::operator()(const GiNaC::ex& e) const {
  GiNaC::ex result = 0;
  std::vector<GiNaC::ex> explicit_partials;
  const ExSet symbols = own_symbols(e);
  const std::vector<GiNaC::ex> intermediates = direct_intermediates(e);
  {
    const ExplicitDerivatives explicit_only;
    for (const GiNaC::ex& z : symbols) {
      const GiNaC::ex Dz = of_symbol(z);
      if (!Dz.is_zero()) result += partial_derivative(e, GiNaC::ex_to<GiNaC::symbol>(z)) * Dz;
    }
    for (const GiNaC::ex& d : intermediates)
      explicit_partials.push_back(partial_derivative(e, GiNaC::ex_to<GiNaC::symbol>(d)));
  }
  for (std::size_t k = 0; k < intermediates.size(); ++k)
    if (!explicit_partials[k].is_zero())
      result += explicit_partials[k] * as_intermediate(intermediates[k]).total_derivative(*this);
  return result;
}

}  // namespace nhc
