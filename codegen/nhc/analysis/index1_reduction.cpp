#include "nhc/expr/work_stage.hpp"
#include "nhc/analysis/index1_reduction.hpp"

#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>

#include "nhc/analysis/dae_system.hpp"
#include "nhc/analysis/numeric_evaluation.hpp"
#include "nhc/derive/euler_operator.hpp"
#include "nhc/expr/intermediate.hpp"
#include "nhc/expr/partial_derivative.hpp"
#include "nhc/expr/stable_symbol.hpp"

namespace nhc {

Index1System reduce_to_index1(const Scene& scene, const DerivedModel& model) {
  const work_budget::Stage stage("reducing to index 1");
  return refusing_at(scene.file_location(), "reducing the " + to_string(model.kind) + " model to index 1",
                     [&] { return reduce_to_index1(analyze_structure(dae_system_of(scene, model))); });
}

Index1System reduce_to_index1(const Scene& scene, const StructuralAnalysis& analysis) {
  const work_budget::Stage stage("reducing to index 1");
  return refusing_at(scene.file_location(), "reducing the " + to_string(analysis.system.model) + " model to index 1",
                     [&] { return reduce_to_index1(analysis); });
}

Index1System reduce_to_index1(const StructuralAnalysis& a) {
  a.require_nonsingular();
  const DaeSystem& sys = a.system;
  const JetSpace& jet = *sys.jet;
  const int n = sys.size();
  Index1System out;
  out.model = sys.model;
  out.jet = sys.jet;
  out.c = a.offsets.c;
  out.d = a.offsets.d;

  // States, in unknown order: x_j, …, x_j^(d_j−1), or x_j alone (algebraic) when d_j = 0.
  std::vector<int> first_state(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) {
    const Unknown& u = sys.unknowns[static_cast<std::size_t>(j)];
    first_state[static_cast<std::size_t>(j)] = static_cast<int>(out.states.size());
    const int count = std::max(a.d(j), 1);
    for (int k = 0; k < count; ++k) out.states.push_back({u.kind, u.index, k, a.d(j) >= 1, sys.derivative_name(j, k)});
  }
  for (int k = 0; k < out.size(); ++k) {
    const std::string idx = std::to_string(k);
    out.y.push_back(stable_symbol("y[" + idx + "]", "y_{" + idx + "}"));
    out.yp.push_back(stable_symbol("yp[" + idx + "]", "\\dot{y}_{" + idx + "}"));
  }
  auto state = [&](int j, int k) { return static_cast<std::size_t>(first_state[static_cast<std::size_t>(j)] + k); };
  for (int j = 0; j < n; ++j) {
    for (int k = 0; k < std::max(a.d(j), 1); ++k) out.jet_to_state[sys.unknown_symbol(j, k)] = out.y[state(j, k)];
    if (a.d(j) >= 1) out.jet_to_state[sys.unknown_symbol(j, a.d(j))] = out.yp[state(j, a.d(j) - 1)];
  }
  auto to_state = [&](const GiNaC::ex& e) {
    const GiNaC::ex s = out.in_states(e);
    if (!jet.jet_coordinates_in(s).empty())
      throw std::logic_error("index-1 reduction left a jet symbol without a state");
    return s;
  };

  // 1. D^{c_i} f_i.
  for (int i = 0; i < n; ++i) {
    out.residuals.push_back(to_state(differentiated_equation(a, i, a.c(i))));
    out.residual_names.push_back(derivative_equation_name(sys.equation_names[static_cast<std::size_t>(i)], a.c(i)));
  }
  // 2. Chain rows yp[x^(k)] − y[x^(k+1)], k = 0..d_j−2.
  for (int j = 0; j < n; ++j)
    for (int k = 0; k + 2 <= a.d(j); ++k) {
      out.residuals.push_back(out.yp[state(j, k)] - out.y[state(j, k + 1)]);
      out.residual_names.push_back("chain " + sys.derivative_name(j, k) + "' = " + sys.derivative_name(j, k + 1));
    }
  if (out.residuals.size() != out.states.size())
    throw std::logic_error("index-1 reduction: residual and state counts differ");

  // Hidden constraints D^r f_i, r < c_i (suslov: the monitored constraints on initial data),
  // with their Jacobians in y: the same list the analysis' consistent point satisfies.
  // Each row is differentiated only by the states that occur in g and stores only those, so the
  // work grows with the size of the constraints, not with (constraints × states).
  std::map<GiNaC::ex, std::size_t, GiNaC::ex_is_less> state_of_symbol;
  for (std::size_t k = 0; k < out.y.size(); ++k) state_of_symbol[out.y[k]] = k;
  for (const InitialValueConstraint& c : initial_value_constraints(a)) {
    const GiNaC::ex g = to_state(c.expression);
    out.hidden_constraints.push_back(g);
    out.hidden_constraint_names.push_back(c.name);
    std::set<std::size_t> occurring;
    for (const GiNaC::ex& symbol : symbols_through(g))
      if (const auto found = state_of_symbol.find(symbol); found != state_of_symbol.end())
        occurring.insert(found->second);
    std::vector<std::pair<int, GiNaC::ex>> row;
    for (std::size_t k : occurring) {
      GiNaC::ex derivative = simplify_expression(partial_derivative(g, out.y[k]));
      if (!derivative.is_zero()) row.emplace_back(static_cast<int>(k), std::move(derivative));
    }
    out.hidden_constraint_jacobian.push_back(std::move(row));
  }
  return out;
}

void initial_state(const Index1System& system, const ConsistentPoint& point, std::vector<double>& y0,
                   std::vector<double>& yp0) {
  y0.assign(static_cast<std::size_t>(system.size()), 0.0);
  yp0.assign(static_cast<std::size_t>(system.size()), 0.0);
  const JetSpace& jet = *system.jet;
  for (int k = 0; k < system.size(); ++k) {
    const StateComponent& s = system.states[static_cast<std::size_t>(k)];
    y0[static_cast<std::size_t>(k)] =
        evaluate_real(jet.symbol({s.kind, s.index, s.order}), point.point, "initial value of " + s.name);
    if (s.differential)
      yp0[static_cast<std::size_t>(k)] =
          evaluate_real(jet.symbol({s.kind, s.index, s.order + 1}), point.point, "initial derivative of " + s.name);
  }
}

}  // namespace nhc
