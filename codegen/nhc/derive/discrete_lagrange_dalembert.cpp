// The discrete Lagrange–d'Alembert step (discrete_lagrange_dalembert.hpp, docs/variational.md).
#include "nhc/derive/discrete_lagrange_dalembert.hpp"

#include <string>

#include "nhc/errors.hpp"
#include "nhc/expr/partial_derivative.hpp"
#include "nhc/expr/symbol_substitution.hpp"

namespace nhc {

namespace {

using GiNaC::ex;

std::vector<GiNaC::realsymbol> symbols(const std::string& stem, int count) {
  std::vector<GiNaC::realsymbol> out;
  for (int i = 0; i < count; ++i) out.push_back(stable_symbol(stem + std::to_string(i)));
  return out;
}

}  // namespace

void require_variational_scene(const Scene& scene, ModelKind model) {
  if (model != ModelKind::chetaev)
    throw InputError(scene.file_location(),
                     "the variational integrator takes the chetaev model, not " + to_string(model) +
                         " (docs/variational.md: the discrete Lagrange-d'Alembert equations are the chetaev "
                         "model's; discrete vakonomic equations are not generated)");
  const JetSpace& jet = *scene.jet;
  const auto refuse = [&](const SourceLocation& where, const std::string& what) {
    throw InputError(where, what +
                                "; the variational integrator (docs/variational.md) takes a "
                                "Lagrangian L(t, q, q'), forces Q(t, q, q') and constraints of order 0 or 1 "
                                "(use IDA: --integrator ida)");
  };
  if (jet.highest_coordinate_order(scene.lagrangian) > 1)
    refuse(scene.lagrangian_where, "the Lagrangian holds second or higher derivatives");
  for (const ex& q : scene.forces)
    if (jet.highest_coordinate_order(q) > 1) refuse(scene.file_location(), "a force holds accelerations");
  for (std::size_t a = 0; a < scene.constraints.size(); ++a) {
    if (jet.highest_coordinate_order(scene.constraints[a]) > 1)
      refuse(scene.file_location(), "constraint f" + std::to_string(a + 1) + " = " + scene.constraint_texts.at(a) +
                                        " has order " +
                                        std::to_string(jet.highest_coordinate_order(scene.constraints[a])));
    for (const JetCoordinate& c : jet.jet_coordinates_in(scene.constraints[a]))
      if (c.kind == VariableKind::multiplier)
        refuse(scene.file_location(), "constraint f" + std::to_string(a + 1) + " holds a multiplier");
  }
  const int unknowns = scene.coordinate_count() + scene.constraint_count();
  if (unknowns > kMaxVariationalUnknowns)
    throw InputError(scene.file_location(),
                     "the scene has " + std::to_string(unknowns) + " coordinates and multipliers, more than the " +
                         std::to_string(kMaxVariationalUnknowns) +
                         " the variational integrator's dense Newton matrix takes (docs/variational.md; use IDA: "
                         "--integrator ida)");
}

DiscreteLagrangeDAlembert discrete_lagrange_dalembert(const Scene& scene, ModelKind model) {
  require_variational_scene(scene, model);
  const JetSpace& jet = *scene.jet;
  const int n = jet.coordinate_count(), g = scene.constraint_count();
  DiscreteLagrangeDAlembert d;
  d.increment_previous = symbols("dqprev", n);
  d.q = symbols("qk", n);
  d.momentum_in = symbols("mk", n);
  d.x = symbols("x", n + g);
  const ex t = jet.time(), h = d.h;

  // The midpoint of the step (q_k, q_{k+1}) and the node q_k, as substitutions of the jet
  // symbols: every intermediate gets one image per substitution, shared by all that use it.
  GiNaC::exmap midpoint_map, node_map, end_map;
  midpoint_map[t] = t + h / 2;
  end_map[t] = t + h;
  for (int i = 0; i < n; ++i) {
    const ex qk = d.q[static_cast<std::size_t>(i)], dq = d.x[static_cast<std::size_t>(i)];
    midpoint_map[jet.q(i, 0)] = qk + dq / 2;
    midpoint_map[jet.q(i, 1)] = dq / h;
    node_map[jet.q(i, 0)] = qk;
    node_map[jet.q(i, 1)] = (dq + d.increment_previous[static_cast<std::size_t>(i)]) / (2 * h);
    end_map[jet.q(i, 0)] = qk + dq;
  }
  const SymbolSubstitution midpoint(midpoint_map), node(node_map), end(end_map);

  d.residual.assign(static_cast<std::size_t>(n + g), 0);
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const ex momentum = partial_derivative(scene.lagrangian, GiNaC::ex_to<GiNaC::symbol>(jet.q(i, 1)));
    const ex force = k < scene.forces.size() ? scene.forces[k] : ex(0);
    const ex half_force =
        midpoint(partial_derivative(scene.lagrangian, GiNaC::ex_to<GiNaC::symbol>(jet.q(i, 0))) + force) / 2;
    const ex momentum_plus = midpoint(momentum);
    d.momentum.push_back(momentum);
    d.residual[k] = (d.momentum_in[k] - momentum_plus) / h + half_force;
    d.momentum_out.push_back(momentum_plus + h * half_force);
  }
  for (int a = 0; a < g; ++a) {
    const ex& f = scene.constraints[static_cast<std::size_t>(a)];
    const int m = jet.highest_coordinate_order(f);
    const ex lambda = d.x[static_cast<std::size_t>(n + a)];
    for (const JetCoordinate& c : jet.jet_coordinates_in(f))
      if (c.kind == VariableKind::coordinate && c.order == m)
        d.residual[static_cast<std::size_t>(c.index)] +=
            d.w * lambda * node(partial_derivative(f, GiNaC::ex_to<GiNaC::symbol>(jet.symbol(c))));
    // A constraint without coordinates (m = −1) is a condition on t and the parameters alone:
    // it holds or not at every step, as it does at the end point.
    d.residual[static_cast<std::size_t>(n + a)] = m == 1 ? midpoint(f) : end(f);
  }
  return d;
}

}  // namespace nhc
