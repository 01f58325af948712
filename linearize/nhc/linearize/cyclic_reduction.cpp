#include "nhc/linearize/cyclic_reduction.hpp"

#include <algorithm>

#include "nhc/errors.hpp"
#include "nhc/base/primed_name.hpp"
#include "nhc/expr/intermediate.hpp"
#include "nhc/expr/symbol_substitution.hpp"
#include "nhc/expr/zero_test.hpp"
#include "nhc/expr/work_budget.hpp"

namespace nhc {

namespace {

/// Whether f depends on `symbol` as a function. Over named intermediates the form can name a
/// symbol that cancels (a wheel angle entering only through sin² + cos²), so a dependence the
/// form shows only through intermediates is confirmed by ∂f/∂symbol at sample points.
bool truly_depends_on(const GiNaC::ex& f, const GiNaC::ex& symbol) {
  if (!depends_on(f, symbol)) return false;
  if (f.has(symbol) && direct_intermediates(f).empty()) return true;
  return !vanishes_at_sample_points(f.diff(GiNaC::ex_to<GiNaC::symbol>(symbol)));
}

bool any_has(const std::vector<GiNaC::ex>& expressions, const GiNaC::ex& symbol) {
  for (const GiNaC::ex& e : expressions)
    if (truly_depends_on(e, symbol)) return true;
  return false;
}

/// Index of the state holding x_j^(order) for the unknown that `s` belongs to, or -1.
int find_state(const Index1System& system, const StateComponent& s, int order) {
  for (int k = 0; k < system.size(); ++k) {
    const StateComponent& o = system.states[static_cast<std::size_t>(k)];
    if (o.kind == s.kind && o.index == s.index && o.order == order) return k;
  }
  return -1;
}

}  // namespace

void require_autonomous(const Index1System& system, const GiNaC::ex& time) {
  for (std::size_t r = 0; r < system.residuals.size(); ++r)
    if (depends_on(system.residuals[r], time))
      throw MathError("the residual " + system.residual_names[r] +
                      " depends on t explicitly: a non-autonomous system has no equilibria to linearize about");
  for (std::size_t r = 0; r < system.hidden_constraints.size(); ++r)
    if (depends_on(system.hidden_constraints[r], time))
      throw MathError("the hidden constraint " + system.hidden_constraint_names[r] +
                      " depends on t explicitly: a non-autonomous system has no equilibria to linearize about");
}

namespace {

std::vector<std::vector<GiNaC::ex>> jacobian(const std::vector<GiNaC::ex>& functions,
                                             const std::vector<ReducedComponent>& components, bool derivative) {
  std::vector<std::vector<GiNaC::ex>> out(functions.size(), std::vector<GiNaC::ex>(components.size(), 0));
  for (std::size_t r = 0; r < functions.size(); ++r)
    for (std::size_t c = 0; c < components.size(); ++c) {
      const ReducedComponent& z = components[c];
      if (derivative && !z.differential) continue;
      const GiNaC::ex& symbol = derivative ? z.derivative : z.value;
      out[r][c] = functions[r].diff(GiNaC::ex_to<GiNaC::symbol>(symbol));
    }
  return out;
}

}  // namespace

CyclicReduction reduce_cyclic(const Index1System& system, const GiNaC::ex& time, const std::vector<std::string>& keep,
                              bool autonomous) {
  if (autonomous) require_autonomous(system, time);
  CyclicReduction out;
  std::vector<bool> drop_residual(system.residuals.size(), false);

  for (int k = 0; k < system.size(); ++k) {
    const StateComponent& s = system.states[static_cast<std::size_t>(k)];
    const GiNaC::ex& y = system.y[static_cast<std::size_t>(k)];
    const GiNaC::ex& yp = system.yp[static_cast<std::size_t>(k)];
    ReducedComponent z{y,       s.differential ? yp : GiNaC::ex(0), s.differential, s.name,
                       s.order, s.kind == VariableKind::multiplier};
    const bool position = s.kind == VariableKind::coordinate && s.order == 0 && s.differential;
    if (!position || any_has(system.hidden_constraints, y)) {
      out.components.push_back(z);
      continue;
    }
    // Residuals other than the chain row q' − y[q'] that contain y[q] make q non-cyclic.
    const int velocity = find_state(system, s, 1);
    int chain_row = -1;
    bool appears = false;
    for (std::size_t r = 0; r < system.residuals.size(); ++r) {
      const GiNaC::ex& f = system.residuals[r];
      const bool is_chain = velocity >= 0 && depends_on(f, yp) &&
                            work_budget::is_zero(f - (yp - system.y[static_cast<std::size_t>(velocity)]));
      if (is_chain) chain_row = static_cast<int>(r);
      else if (truly_depends_on(f, y)) appears = true;
    }
    if (appears) {
      out.components.push_back(z);
      continue;
    }
    if (std::find(keep.begin(), keep.end(), s.name) != keep.end()) {
      out.kept.push_back(s.name);
      out.components.push_back(z);
      continue;
    }
    out.cyclic.push_back(s.name);
    if (chain_row >= 0) {
      drop_residual[static_cast<std::size_t>(chain_row)] = true;  // d_q ≥ 2: q' is a state already
    } else {
      // d_q = 1: the residual holds q' as the derivative of q; it becomes an algebraic state.
      out.components.push_back({yp, GiNaC::ex(0), false, base::primed_name(s.name, 1), 1, false});
    }
  }
  // A cyclic position can still be named inside intermediates, where it cancels: any value
  // gives the same function, so 0 removes it from what the numeric programs read.
  GiNaC::exmap cyclic_to_zero;
  for (int k = 0; k < system.size(); ++k) {
    const StateComponent& s = system.states[static_cast<std::size_t>(k)];
    if (std::find(out.cyclic.begin(), out.cyclic.end(), s.name) != out.cyclic.end())
      cyclic_to_zero[system.y[static_cast<std::size_t>(k)]] = 0;
  }
  const SymbolSubstitution without_cyclic(cyclic_to_zero);
  for (std::size_t r = 0; r < system.residuals.size(); ++r)
    if (!drop_residual[r]) {
      out.residuals.push_back(without_cyclic(system.residuals[r]));
      out.residual_names.push_back(system.residual_names[r]);
    }
  for (const GiNaC::ex& g : system.hidden_constraints) out.hidden.push_back(without_cyclic(g));
  out.hidden_names = system.hidden_constraint_names;
  out.dF_dz = jacobian(out.residuals, out.components, false);
  out.dF_dzp = jacobian(out.residuals, out.components, true);
  out.dg_dz = jacobian(out.hidden, out.components, false);
  return out;
}

}  // namespace nhc
