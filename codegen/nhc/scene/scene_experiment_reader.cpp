// The experiment's tables of a scene file: [initial], [simulate], [events], [contacts],
// [controller] (docs/architecture.md, "The scene's three parts").
#include "nhc/scene/scene_reader.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <iostream>

#include <fmt/format.h>

#include "nhc/io/input_file.hpp"
#include "nhc/base/number_text.hpp"
#include "nhc/expr/intermediate.hpp"
#include "nhc/expr/work_budget.hpp"
#include "nhc/scene/definition_table.hpp"
#include "nhc/scene/constant_expression.hpp"
#include "nhc/scene/expression_parser.hpp"
#include "nhc/scene/tolerances.hpp"
#include "nhc/scene/toml_text_check.hpp"
#include "nhc/expr/work_stage.hpp"
#include "nhc/expr/zero_test.hpp"
#include "nhc/scene/scene.hpp"
#include "nhc/scene/scene_text.hpp"

namespace nhc::scene_reading {

/// [events]: name = { when = "expression", direction = "up"|"down"|"any", action =
/// "stop"|"record" } (docs/scenes.md); the expression may use what [outputs] may.
void SceneReader::read_events(const toml::table& root, Scene& scene, const ExpressionRules& rules) {
  const toml::node* node = root.get("events");
  if (!node) return;
  for (const auto& [key, value] : entries_in_file_order(*node, "events")) {
    const std::string n(key->str());
    check_variable_name_at(at(key->source()), n, "event");
    const toml::table* t = value->as_table();
    if (!t)
      fail(*value,
           "event '" + n + "' must be a table: { when = \"expression\", direction = \"up\", action = \"stop\" }");
    check_keys(*t, {"when", "direction", "action"});
    const toml::node& when = require(*t, "when", "events." + n);
    SceneEvent event;
    event.name = n;
    event.text = string_value(when, "when");
    event.expression = expression(when, "event '" + n + "'", *scene.jet, multipliers_allowed(rules));
    event.where = at(when);
    if (const toml::node* d = t->get("direction")) {
      const std::string text = string_value(*d, "direction");
      if (text == "up") event.direction = EventDirection::up;
      else if (text == "down") event.direction = EventDirection::down;
      else if (text == "any") event.direction = EventDirection::any;
      else fail(*d, "direction '" + printable(text) + "': up, down or any");
    }
    if (const toml::node* a = t->get("action")) {
      const std::string text = string_value(*a, "action");
      if (text == "stop") event.action = EventAction::stop;
      else if (text == "record") event.action = EventAction::record;
      else fail(*a, "action '" + printable(text) + "': stop or record");
    }
    scene.events.push_back(std::move(event));
  }
}

/// [contacts.NAME]: normal = "expression" (or a multiplier's name), rolling = [1-based constraint
/// indices], mu = number >= 0, on_slip = "stop"|"slide" (docs/scenes.md, "Contacts").
void SceneReader::read_contacts(const toml::table& root, Scene& scene, const ExpressionRules& rules) {
  const toml::node* node = root.get("contacts");
  if (!node) return;
  std::set<int> claimed;  // a rolling constraint belongs to one contact
  for (const auto& [key, value] : entries_in_file_order(*node, "contacts")) {
    const std::string n(key->str());
    check_variable_name_at(at(key->source()), n, "contact");
    const toml::table* t = value->as_table();
    if (!t)
      fail(*value, "contact '" + n + "' must be a table: [contacts." + n +
                       "] with normal = \"m*g\", rolling = [1, 2], mu = 0.5");
    check_keys(*t, {"normal", "rolling", "mu", "on_slip"});
    SceneContact contact;
    contact.name = n;
    contact.where = at(key->source());
    const toml::node& normal = require(*t, "normal", "contacts." + n);
    contact.normal_text = string_value(normal, "normal");
    contact.normal =
        expression(normal, "the normal force of contact '" + n + "'", *scene.jet, multipliers_allowed(rules));
    const toml::node& rolling = require(*t, "rolling", "contacts." + n);
    const toml::array& indices = array_value(rolling, "rolling");
    if (indices.empty()) fail(rolling, "'rolling' of contact '" + n + "' is empty: name the rolling constraints");
    for (const toml::node& i : indices) {
      if (!i.is_integer()) fail(i, "a rolling constraint is a 1-based index into 'constraints', not " + type_name(i));
      const int64_t k = *i.value<int64_t>();
      if (k < 1 || k > scene.constraint_count())
        fail(i, "rolling constraint " + std::to_string(k) + " is not one of the scene's " +
                    std::to_string(scene.constraint_count()) + " constraints (1-based)");
      if (!claimed.insert(static_cast<int>(k)).second)
        fail(i, "constraint " + std::to_string(k) + " is already a rolling constraint of a contact");
      contact.rolling.push_back(static_cast<int>(k - 1));
    }
    const toml::node& mu = require(*t, "mu", "contacts." + n);
    contact.mu = number_value(mu, "mu");
    contact.mu_expression = number_expression(mu);
    if (contact.mu < 0) fail(mu, "mu must not be negative");
    if (const toml::node* s = t->get("on_slip")) {
      const std::string text = string_value(*s, "on_slip");
      if (text == "stop") contact.on_slip = SlipAction::stop;
      else if (text == "slide") contact.on_slip = SlipAction::slide;
      else fail(*s, "on_slip '" + printable(text) + "': stop or slide");
      contact.on_slip_where = at(*s);
    }
    scene.contacts.push_back(std::move(contact));
  }
}

/// [controller]: period = h > 0, states = { z = value }, inputs = { U = "law" } (each an
/// [inputs] entry without a law of its own), update = { z = "next value" } (one per state).
/// The expressions may use what a feedback law may, the states, and `period` (docs/scenes.md).
void SceneReader::read_controller(const toml::table& root, Scene& scene, const ExpressionRules& rules) {
  const toml::node* node = root.get("controller");
  if (!node) return;
  const toml::table& table = table_value(*node, "controller");
  check_keys(table, {"period", "states", "inputs", "update", "mpc"});
  SceneController& controller = scene.controller;
  controller.present = true;
  controller.where = at(*node);
  if (controller.where.line <= 0) controller.where = scene.file_location();
  const toml::node& period = require(table, "period", "controller");
  controller.period = number_value(period, "period");
  controller.period_where = at(period);
  controller.period_expression = number_expression(period);
  if (!(controller.period > 0)) fail(period, "period must be a positive number (the controller's sample period h)");
  const JetSpace& jet = *scene.jet;
  if (const toml::node* mpc = table.get("mpc")) read_mpc(*mpc, table, scene);
  std::map<std::string, int> state_index;
  if (const toml::node* states = table.get("states")) {
    for (const auto& [key, value] : entries_in_file_order(*states, "controller.states")) {
      const std::string n(key->str());
      if (jet.coordinate_index(n))
        throw InputError(at(key->source()),
                         "controller state '" + printable(n) +
                             "' is named like a coordinate: a discrete state needs a name of its own");
      if (n == "period")
        throw InputError(at(key->source()), "'period' is the controller's sample period, not a state name");
      check_variable_name_at(at(key->source()), n, "controller state");
      SceneControllerState state{n, number_value(*value, "controller state '" + n + "'"), GiNaC::symbol(n),
                                 at(key->source()), number_expression(*value)};
      state_index[n] = static_cast<int>(controller.states.size());
      controller.states.push_back(state);
    }
  }
  // The states and `period` are names of the controller's expressions; the rest is the scene's.
  ExpressionRules law = rules;
  law.allow_multipliers = false;
  law.allow_inputs = false;  // the controller sets inputs; it does not read them
  law.input_law = nullptr;
  // `period` in the laws is the period's expression of the parameters, so that it follows them.
  const GiNaC::ex h = period.is_string() ? expression(period, "the controller's period", jet, rules)
                                         : GiNaC::ex(GiNaC::numeric(controller.period));
  law.definition = [&controller, state_index, h,
                    outer = rules.definition](const std::string& name) -> std::optional<Value> {
    if (const auto it = state_index.find(name); it != state_index.end())
      return Value::scalar(controller.states[static_cast<std::size_t>(it->second)].symbol);
    if (name == "period") return Value::scalar(h);
    return outer ? outer(name) : std::nullopt;
  };
  auto read_law = [&](const toml::node& value, int target, const std::string& name, const std::string& what) {
    SceneControllerLaw entry;
    entry.target = target;
    entry.name = name;
    if (value.is_number()) {
      entry.expression = number_value(value, what);
      entry.text = shortest(GiNaC::ex_to<GiNaC::numeric>(entry.expression).to_double());
    } else {
      entry.text = string_value(value, what);
      entry.expression = expression(value, what, jet, law);
    }
    entry.where = at(value);
    return entry;
  };
  if (const toml::node* inputs = table.get("inputs")) {
    for (const auto& [key, value] : entries_in_file_order(*inputs, "controller.inputs")) {
      const std::string n(key->str());
      const std::optional<int> k = jet.input_index(n);
      if (!k)
        throw InputError(at(key->source()), "[controller] sets '" + printable(n) +
                                                "', which is not an [inputs] entry (the controller drives inputs)");
      const SceneInput& input = scene.inputs.at(static_cast<std::size_t>(*k));
      if (input.feedback)
        throw InputError(at(key->source()), "[controller] sets input '" + n +
                                                "', whose [inputs] entry is a feedback law (" + input.where.str() +
                                                "): an input has one law; give it a signal there");
      controller.inputs.push_back(read_law(*value, *k, n, "controller input '" + n + "'"));
    }
  }
  std::vector<const toml::node*> updates(controller.states.size(), nullptr);
  if (const toml::node* update = table.get("update")) {
    for (const auto& [key, value] : entries_in_file_order(*update, "controller.update")) {
      const std::string n(key->str());
      const auto it = state_index.find(n);
      if (it == state_index.end())
        throw InputError(at(key->source()), "[controller] update names '" + printable(n) +
                                                "', which is not one of the controller's states");
      updates[static_cast<std::size_t>(it->second)] = value;
    }
  }
  for (std::size_t i = 0; i < controller.states.size(); ++i) {
    const SceneControllerState& state = controller.states[i];
    if (!updates[i])
      throw InputError(state.where, "controller state '" + state.name + "' has no update (update = { " + state.name +
                                        " = \"its next value\" })");
    controller.update.push_back(
        read_law(*updates[i], static_cast<int>(i), state.name, "update of '" + state.name + "'"));
  }
}

/// `mpc = { horizon = H, intervals = N, max_iterations = M, tolerance = E, warm_start = B }`:
/// model predictive control of every [inputs] input (docs/mpc.md); beside it the table holds
/// only `period`.
void SceneReader::read_mpc(const toml::node& node, const toml::table& controller, Scene& scene) {
  const toml::table* table = node.as_table();
  if (!table) fail(node, "mpc must be a table: mpc = { horizon = 1.5, intervals = 15 }");
  check_keys(*table, {"horizon", "intervals", "max_iterations", "tolerance", "warm_start"});
  for (const char* other : {"inputs", "states", "update"})
    if (const toml::node* n = controller.get(other))
      fail(*n, std::string("[controller] with mpc: the model predictive controller sets every input of [inputs]; '") +
                   other + "' goes with a controller of laws, not with mpc");
  SceneMpc& mpc = scene.controller.mpc;
  mpc.present = true;
  mpc.where = at(node);
  const toml::node& horizon = require(*table, "horizon", "controller.mpc");
  mpc.horizon = number_value(horizon, "horizon");
  if (!(std::isfinite(mpc.horizon) && mpc.horizon > 0))
    fail(horizon, "horizon must be a positive number (the prediction horizon in time)");
  if (!(mpc.horizon >= scene.controller.period))
    fail(horizon, "horizon " + shortest(mpc.horizon) + " is shorter than the period " +
                      shortest(scene.controller.period) + ": each plan must reach the next sample");
  const toml::node& intervals = require(*table, "intervals", "controller.mpc");
  const std::optional<int64_t> n = intervals.value_exact<int64_t>();
  if (!n || *n < 1 || *n > 10000)
    fail(intervals, "intervals must be a whole number from 1 to 10000 (the horizon's mesh)");
  mpc.intervals = static_cast<int>(*n);
  if (const toml::node* m = table->get("max_iterations")) {
    const std::optional<int64_t> k = m->value_exact<int64_t>();
    if (!k || *k < 1 || *k > 1000000) fail(*m, "max_iterations must be a whole number from 1 to 1000000");
    mpc.max_iterations = static_cast<int>(*k);
  }
  if (const toml::node* e = table->get("tolerance")) {
    mpc.tolerance = number_value(*e, "tolerance");
    if (!(std::isfinite(mpc.tolerance) && mpc.tolerance > 0 && mpc.tolerance < 1))
      fail(*e, "tolerance must be a number between 0 and 1 (IPOPT's tol of each solve)");
  }
  if (const toml::node* w = table->get("warm_start")) {
    const std::optional<bool> b = w->value_exact<bool>();
    if (!b) fail(*w, "warm_start must be true or false");
    mpc.warm_start = *b;
  }
}

/// Parameters and given initial values q_i^(k)(t0): where omega() checks a matrix numerically.
GiNaC::exmap SceneReader::initial_point_of(const Scene& scene) {
  GiNaC::exmap point = scene.parameter_substitution();
  point[scene.jet->time()] = scene.initial.t0;
  const auto& coords = scene.jet->coordinates();
  for (std::size_t i = 0; i < coords.size(); ++i) {
    const auto it = scene.initial.values.find(coords[i]);
    if (it == scene.initial.values.end()) continue;
    for (std::size_t k = 0; k < it->second.size(); ++k)
      point[scene.jet->q(static_cast<int>(i), static_cast<int>(k))] = it->second[k];
  }
  return point;
}

void SceneReader::read_initial(const toml::table& root, Scene& scene) {
  const toml::node* node = root.get("initial");
  if (!node) return;
  const toml::table& table = table_value(*node, "initial");
  const JetSpace& jet = *scene.jet;
  for (auto&& [key, value] : table) {
    const std::string n(key.str());
    if (n == "t0") {
      scene.initial.t0 = number_value(value, "initial t0");
      scene.initial.t0_expression = number_expression(value);
      continue;
    }
    if (n == "fixed") {
      for (const toml::node& f : array_value(value, "initial fixed")) fixed_nodes_.push_back(&f);
      continue;
    }
    bool known = jet.coordinate_index(n).has_value();
    for (int a = 0; !known && a < jet.multiplier_count(); ++a) known = jet.multiplier_name(a) == n;
    if (!known)
      throw InputError(at(key.source()), "[initial] names '" + printable(n) +
                                             "', which is neither t0, a coordinate nor a "
                                             "multiplier of this scene");
    const toml::array& arr = array_value(value, "initial " + n);
    if (arr.empty()) fail(value, "initial values of '" + n + "' are empty");
    if (arr.size() > static_cast<std::size_t>(kMaxDerivativeOrder) + 1)
      fail(value, "initial values of '" + n + "' go beyond derivative order " + std::to_string(kMaxDerivativeOrder));
    std::vector<double> values;
    std::vector<std::string> texts;
    for (const toml::node& v : arr) {
      values.push_back(number_value(v, "initial value of " + n));
      texts.push_back(v.is_string() ? *v.value<std::string>() : std::string());
    }
    scene.initial.values[n] = values;
    if (std::any_of(texts.begin(), texts.end(), [](const std::string& e) { return !e.empty(); }))
      scene.initial.expressions[n] = texts;
  }
  check_fixed(scene);
}

/// [initial] fixed: each entry a given value, "x" or "x'" (as many primes as its order).
void SceneReader::check_fixed(Scene& scene) {
  for (const toml::node* f : fixed_nodes_) {
    const std::string name = string_value(*f, "initial fixed entry");
    const std::size_t primes = name.size() - std::min(name.size(), name.find_last_not_of('\'') + 1);
    const std::string base = name.substr(0, name.size() - primes);
    const auto it = scene.initial.values.find(base);
    if (it == scene.initial.values.end() || primes >= it->second.size())
      fail(*f, "fixed names '" + printable(name) + "', which is not a value given in [initial]");
    scene.initial.fixed.push_back(name);
  }
}

void SceneReader::read_simulate(const toml::table& root, Scene& scene) {
  const toml::node* node = root.get("simulate");
  if (!node) {
    scene.simulate.t_end = scene.initial.t0 + 1.0;
    return;
  }
  const toml::table& table = table_value(*node, "simulate");
  check_keys(table, {"model", "t_end", "rtol", "atol", "outputs", "max_step", "initial_step"});
  scene.simulate.t_end = scene.initial.t0 + 1.0;
  if (const toml::node* m = table.get("model")) {
    const std::string n = string_value(*m, "simulate model");
    auto kind = parse_model_kind(n);
    if (!kind) fail(*m, "unknown model '" + printable(n) + "' (known: " + model_name_list() + ")");
    if (std::find(scene.models.begin(), scene.models.end(), *kind) == scene.models.end())
      fail(*m, "model '" + n + "' is not among the scene's models");
    scene.simulate.model = kind;
  }
  if (const toml::node* te = table.get("t_end")) {
    scene.simulate.t_end = number_value(*te, "t_end");
    scene.simulate.t_end_expression = number_expression(*te);
    if (!(scene.simulate.t_end > scene.initial.t0)) fail(*te, "t_end must be after t0 = " + shortest(scene.initial.t0));
  }
  if (const toml::node* n = table.get("outputs")) {
    const std::optional<int64_t> count = n->value_exact<int64_t>();
    if (!count || *count < 1 || *count > 10000000) fail(*n, "outputs must be a whole number from 1 to 10000000");
    scene.simulate.outputs = static_cast<int>(*count);
  }
  for (const char* key : {"rtol", "atol"}) {
    if (const toml::node* tol = table.get(key)) {
      const double v = number_value(*tol, key);
      if (!(v > 0)) fail(*tol, std::string(key) + " must be positive");
      if (std::string(key) == "rtol" && !relative_tolerance_problem(v).empty())
        fail(*tol, "rtol = " + shortest(v) + " " + relative_tolerance_problem(v));
      (std::string(key) == "rtol" ? scene.simulate.rtol : scene.simulate.atol) = v;
      (std::string(key) == "rtol" ? scene.simulate.rtol_expression : scene.simulate.atol_expression) =
          number_expression(*tol);
    }
  }
  for (const char* key : {"max_step", "initial_step"}) {
    if (const toml::node* step = table.get(key)) {
      const double v = number_value(*step, key);
      if (!(v > 0)) fail(*step, std::string(key) + " must be positive (a step of IDA's, in the units of t)");
      const bool largest = std::string(key) == "max_step";
      (largest ? scene.simulate.max_step : scene.simulate.initial_step) = v;
      (largest ? scene.simulate.max_step_expression : scene.simulate.initial_step_expression) =
          number_expression(*step);
    }
  }
}

}  // namespace nhc::scene_reading
