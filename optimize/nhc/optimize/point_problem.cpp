#include "nhc/optimize/point_problem.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <set>
#include <sstream>

#include "nhc/analysis/index1_reduction.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/base/primed_name.hpp"
#include "nhc/expr/intermediate.hpp"

namespace nhc::optimize {

namespace {

/// The symbols common to both problems after t, y, y', u: the parameters.
void add_parameters(const Scene& scene, PointProblem& p) {
  for (int q = 0; q < static_cast<int>(scene.parameter_values.size()); ++q)
    p.symbols.push_back(scene.jet->parameter(q));
  p.parameter_values = scene.parameter_values;
}

/// Every symbol e depends on must be one of the problem's: else InputError at `where` naming it.
void check_symbols(const PointProblem& p, const GiNaC::ex& e, const SourceLocation& where, const std::string& what,
                   const std::string& why) {
  const std::set<GiNaC::ex, GiNaC::ex_is_less> known(p.symbols.begin(), p.symbols.end());
  for (const GiNaC::ex& s : symbols_through(e))
    if (!known.count(s)) {
      std::ostringstream name;
      name << s;
      throw InputError(where, what + " uses " + name.str() + ": " + why);
    }
}

/// The bounds and boundary values of the settings on the problem's slots (`slot_of` maps a
/// coordinate's derivative or an input to its slot) and the bounds on named quantities as rows.
template <class SlotOf, class InStates>
void add_bounds(const Scene& scene, const Settings& settings, PointProblem& p, SlotOf slot_of, InStates in_states,
                const std::string& why) {
  for (const PathBound& b : settings.bounds) {
    if (b.quantity.kind == PathQuantity::Kind::output) {
      const SceneQuantity& q = scene.outputs[static_cast<std::size_t>(b.quantity.index)];
      const GiNaC::ex e = in_states(q.expression);
      check_symbols(p, e, b.where, "the named quantity " + q.name, why);
      p.path.push_back({e, fmt::format("the bound {} <= {} <= {}", b.low, q.name, b.high), b.low, b.high});
      continue;
    }
    p.bounds.push_back({slot_of(b.quantity, b.where), b.low, b.high, b.quantity.name, b.where});
  }
  for (const BoundaryValue& b : settings.initial)
    p.initial.push_back({slot_of(b.quantity, b.where), b.low, b.high, b.quantity.name, b.where});
  for (const BoundaryValue& b : settings.final)
    p.final.push_back({slot_of(b.quantity, b.where), b.low, b.high, b.quantity.name, b.where});
}

}  // namespace

PointProblem vakonomic_problem(const Scene& scene, const Settings& settings) {
  const JetSpace& jet = *scene.jet;
  PointProblem p;
  p.states = scene.coordinate_count();
  p.symbols.push_back(jet.time());
  for (int i = 0; i < p.states; ++i) {
    p.state_names.push_back(jet.coordinates()[static_cast<std::size_t>(i)]);
    p.collocated.push_back(true);
    p.symbols.push_back(jet.q(i, 0));
  }
  for (int i = 0; i < p.states; ++i) p.symbols.push_back(jet.q(i, 1));
  add_parameters(scene, p);
  const std::string why =
      "without [inputs] nhc optimize takes t, the coordinates and their first derivatives (the derivatives are the "
      "controls: docs/optimize.md, \"Scope\")";
  const GiNaC::exmap parameters = scene.parameter_substitution();
  p.integrand = settings.objective.subs(parameters);
  check_symbols(p, p.integrand, settings.objective_where, "the objective", why);
  p.final_cost = settings.final_cost.subs(parameters);
  check_symbols(p, p.final_cost, settings.final_cost_where, "final_cost", why);
  for (int a = 0; a < scene.constraint_count(); ++a) {
    const std::string& text = scene.constraint_texts[static_cast<std::size_t>(a)];
    p.path.push_back(
        {scene.constraints[static_cast<std::size_t>(a)].subs(parameters), "the constraint " + text + " = 0"});
    check_symbols(p, p.path.back().expression, scene.file_location(), "the constraint " + text, why);
  }
  auto slot_of = [&](const PathQuantity& q, const SourceLocation& where) {
    if (q.kind == PathQuantity::Kind::input)
      throw InputError(where, "'" + q.name + "' is an input, and the scene has no [inputs]");
    if (q.order > 1)
      throw InputError(
          where,
          "'" + q.name + "': without [inputs] the transcription holds coordinates and their first derivatives only");
    return q.order == 0 ? q.index : p.states + q.index;
  };
  add_bounds(
      scene, settings, p, slot_of, [&](const GiNaC::ex& e) { return e.subs(parameters); }, why);
  return p;
}

PointProblem dynamics_problem(const Scene& scene, const Settings& settings, ModelKind model) {
  const JetSpace& jet = *scene.jet;
  const DerivedModel derived = derive_model(scene, model);
  // The scene asks for a model it cannot have (the Suslov model without its `dependent` speeds, a
  // model for other constraints): a fault of the scene's text, at the `model` entry.
  if (!derived.applicable)
    throw InputError(settings.model ? settings.model_where : settings.table_where,
                     "the " + to_string(model) + " model is not applicable: " + derived.reason);
  const Index1System system = reduce_to_index1(scene, derived);
  PointProblem p;
  p.dynamics = true;
  p.model = model;
  p.states = system.size();
  p.inputs = static_cast<int>(scene.inputs.size());
  p.symbols.push_back(jet.time());
  for (const StateComponent& s : system.states) {
    p.state_names.push_back(s.name);
    p.collocated.push_back(s.differential);
  }
  for (const GiNaC::realsymbol& y : system.y) p.symbols.push_back(y);
  for (const GiNaC::realsymbol& yp : system.yp) p.symbols.push_back(yp);
  for (int k = 0; k < p.inputs; ++k) {
    p.input_names.push_back(scene.inputs[static_cast<std::size_t>(k)].name);
    p.symbols.push_back(jet.input(k));
  }
  add_parameters(scene, p);
  const std::string why =
      "the " + to_string(model) + " model's states hold the coordinates, their derivatives up to " +
      "the order of its equations and the multipliers (docs/optimize.md, \"Two problems from one table\")";
  auto in_states = [&](const GiNaC::ex& e) { return system.in_states(e); };
  p.integrand = in_states(settings.objective);
  check_symbols(p, p.integrand, settings.objective_where, "the objective", why);
  p.final_cost = in_states(settings.final_cost);
  check_symbols(p, p.final_cost, settings.final_cost_where, "final_cost", why);
  p.dynamics_rows = static_cast<int>(system.residuals.size());
  for (std::size_t r = 0; r < system.residuals.size(); ++r)
    p.path.push_back({system.residuals[r],
                      fmt::format("the {} model's equation {} = 0", to_string(model), system.residual_names[r])});
  for (std::size_t r = 0; r < system.hidden_constraints.size(); ++r)
    p.initial_rows.push_back(
        {system.hidden_constraints[r], fmt::format("the hidden constraint {} = 0 of the {} model",
                                                   system.hidden_constraint_names[r], to_string(model))});
  auto slot_of = [&](const PathQuantity& q, const SourceLocation& where) {
    if (q.kind == PathQuantity::Kind::input) return 2 * p.states + q.index;
    const GiNaC::ex e = in_states(jet.q(q.index, q.order));
    for (int k = 0; k < p.states; ++k) {
      if (e.is_equal(system.y[static_cast<std::size_t>(k)])) return k;
      if (e.is_equal(system.yp[static_cast<std::size_t>(k)]) && p.collocated[static_cast<std::size_t>(k)])
        return p.states + k;
    }
    throw InputError(where, "'" + q.name + "' is not among the " + to_string(model) +
                                " model's states and their rates (" + base::primed_name(p.state_names.front(), 0) +
                                ", …)");
  };
  add_bounds(scene, settings, p, slot_of, in_states, why);
  return p;
}

PointProblem point_problem(const Scene& scene, const Settings& settings) {
  if (scene.inputs.empty()) return vakonomic_problem(scene, settings);
  return dynamics_problem(scene, settings, settings.model.value_or(ModelKind::chetaev));
}

}  // namespace nhc::optimize
