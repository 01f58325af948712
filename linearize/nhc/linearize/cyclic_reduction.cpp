#include "nhc/linearize/cyclic_reduction.hpp"

#include "nhc/errors.hpp"
#include "nhc/jet/work_budget.hpp"

namespace nhc {

namespace {

bool any_has(const std::vector<GiNaC::ex>& expressions, const GiNaC::ex& symbol) {
  for (const GiNaC::ex& e : expressions)
    if (e.has(symbol)) return true;
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

void require_autonomous(const Index1System& system, const GiNaC::ex& time) {
  for (std::size_t r = 0; r < system.residuals.size(); ++r)
    if (system.residuals[r].has(time))
      throw MathError("the residual " + system.residual_names[r] +
                      " depends on t explicitly: a non-autonomous system has no equilibria to linearize about");
  for (std::size_t r = 0; r < system.hidden_constraints.size(); ++r)
    if (system.hidden_constraints[r].has(time))
      throw MathError("the hidden constraint " + system.hidden_constraint_names[r] +
                      " depends on t explicitly: a non-autonomous system has no equilibria to linearize about");
}

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

CyclicReduction reduce_cyclic(const Index1System& system, const GiNaC::ex& time) {
  require_autonomous(system, time);
  CyclicReduction out;
  std::vector<bool> drop_residual(system.residuals.size(), false);

  for (int k = 0; k < system.size(); ++k) {
    const StateComponent& s = system.states[static_cast<std::size_t>(k)];
    const GiNaC::ex& y = system.y[static_cast<std::size_t>(k)];
    const GiNaC::ex& yp = system.yp[static_cast<std::size_t>(k)];
    ReducedComponent z{y, s.differential ? yp : GiNaC::ex(0), s.differential, s.name, s.order,
                       s.kind == VariableKind::multiplier};
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
      const bool is_chain = velocity >= 0 && f.has(yp) &&
                            work_budget::is_zero(f - (yp - system.y[static_cast<std::size_t>(velocity)]));
      if (is_chain) chain_row = static_cast<int>(r);
      else if (f.has(y)) appears = true;
    }
    if (appears) {
      out.components.push_back(z);
      continue;
    }
    out.cyclic.push_back(s.name);
    if (chain_row >= 0) {
      drop_residual[static_cast<std::size_t>(chain_row)] = true;  // d_q ≥ 2: q' is a state already
    } else {
      // d_q = 1: the residual holds q' as the derivative of q; it becomes an algebraic state.
      out.components.push_back({yp, GiNaC::ex(0), false, s.name + "'", 1, false});
    }
  }
  for (std::size_t r = 0; r < system.residuals.size(); ++r)
    if (!drop_residual[r]) {
      out.residuals.push_back(system.residuals[r]);
      out.residual_names.push_back(system.residual_names[r]);
    }
  out.hidden = system.hidden_constraints;
  out.hidden_names = system.hidden_constraint_names;
  out.dF_dz = jacobian(out.residuals, out.components, false);
  out.dF_dzp = jacobian(out.residuals, out.components, true);
  out.dg_dz = jacobian(out.hidden, out.components, false);
  return out;
}

}  // namespace nhc
