// The system's tables of a scene file: [parameters] computed from others, [definitions], [inputs],
// [forces], [reference] (docs/architecture.md, "The scene's three parts").
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

/// [definitions]: name = "expression", names checked like parameters, resolved on use.
void SceneReader::read_definitions(const toml::table& root, DefinitionTable& definitions) {
  const toml::node* node = root.get("definitions");
  if (!node) return;
  for (auto&& [key, value] : table_value(*node, "definitions")) {
    const std::string n(key.str());
    check_variable_name_at(at(key.source()), n, "definition");
    const std::string text = string_value(value, "definition '" + n + "'");
    const toml::node* value_node = &value;
    definitions.add(n, text,
                    [this, value_node](std::size_t offset) { return expression_location(*value_node, offset); });
  }
}

/// [reference]: coordinate = "q(t)" for every model; [reference.<model>] for one model.
void SceneReader::read_reference(const toml::node& node, Scene& scene, const ExpressionRules& mechanics) {
  ExpressionRules time_only = mechanics;
  time_only.allow_coordinates = false;
  const auto read_entries = [&](const toml::table& table, const std::string& where) {
    SceneReference::Entries entries;
    for (auto&& [key, value] : table) {
      const std::string n(key.str());
      if (value.is_table()) {
        const auto kind = parse_model_kind(n);
        if (!kind || where != "reference")
          throw InputError(
              at(key.source()),
              "[" + where + "." + printable(n) + "]: " +
                  (where != "reference" ? "a model's reference holds coordinates only"
                                        : "'" + printable(n) + "' is not a model (known: " + model_name_list() + ")"));
        continue;
      }
      const std::optional<int> i = scene.jet->coordinate_index(n);
      if (!i)
        throw InputError(at(key.source()), "[" + where + "] names '" + printable(n) + "', which is not a coordinate");
      entries.emplace_back(*i, expression(value, "reference", *scene.jet, time_only));
    }
    return entries;
  };
  const toml::table& ref = table_value(node, "reference");
  scene.reference.all = read_entries(ref, "reference");
  for (auto&& [key, value] : ref)
    if (const toml::table* model_table = value.as_table()) {
      const std::string n(key.str());
      scene.reference.per_model[*parse_model_kind(n)] = read_entries(*model_table, "reference." + n);
    }
}

/// [forces]: coordinate = "Q(t, q, q')", the generalized force of docs/forces.md.
/// [inputs]: name = "u(t, parameters)" (a number is a constant signal), the default signal.
/// Either may name the [definitions] (`rules` has them): a definition is resolved once, so one
/// that names an input whose entry comes later holds that input's symbol, which a law may not
/// reach (the symbols are searched through the definitions' named intermediates).
void SceneReader::read_input_signals(const std::vector<std::pair<const toml::node*, SourceLocation>>& nodes,
                                     Scene& scene, const ExpressionRules& rules) {
  ExpressionRules signal = rules;
  signal.allow_inputs = false;  // a signal of t, or a feedback law of t, q and q'; no other input
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const toml::node& value = *nodes[k].first;
    const std::string& name = scene.jet->inputs()[k];
    GiNaC::ex u;
    if (value.is_number()) u = number_value(value, "input '" + name + "'");
    else if (value.is_string()) u = expression(value, "input '" + name + "'", *scene.jet, signal);
    else
      fail(value, "input '" + name +
                      "' must be a number or an expression of t, the parameters and the coordinates (a string)");
    for (const GiNaC::ex& s : symbols_through(u))
      if (const std::optional<int> j = scene.jet->input_of(s))
        fail(value, "input '" + name + "' uses input '" + scene.jet->inputs()[static_cast<std::size_t>(*j)] +
                        "' through a definition: an input's law may not use another input");
    const int order = scene.jet->highest_coordinate_order(u);
    // A signal is evaluated by substitution of t and the parameters (Scene::input_substitution),
    // which does not look into named intermediates (SceneOptions::keep_definitions).
    if (order < 0) u = expand_intermediates(u);
    // The equations' states hold q and q' (forces are Q(t, q, q')); q'' is what the input
    // drives, so a law of q'' would be an equation for itself (docs/scenes.md, "Feedback laws").
    if (order > 1)
      fail(value, "input '" + name + "' uses a derivative of order " + std::to_string(order) +
                      " of a coordinate: an algebraic loop (the input drives the accelerations it would "
                      "read); a feedback law may use t, parameters, coordinates and their first derivatives");
    SceneInput input;
    input.name = name;
    input.default_signal = u;
    input.where = nodes[k].second;
    if (order >= 0) {
      input.law = u;
      input.feedback = true;
      input.default_signal = 0;
    }
    scene.inputs.push_back(input);
  }
}

void SceneReader::read_forces(const toml::table& root, Scene& scene, const ExpressionRules& rules) {
  const JetSpace& jet = *scene.jet;
  scene.forces.assign(static_cast<std::size_t>(jet.coordinate_count()), GiNaC::ex(0));
  const toml::node* node = root.get("forces");
  if (!node) return;
  for (auto&& [key, value] : table_value(*node, "forces")) {
    const std::string n(key.str());
    const std::optional<int> i = jet.coordinate_index(n);
    if (!i) throw InputError(at(key.source()), "[forces] names '" + printable(n) + "', which is not a coordinate");
    const GiNaC::ex q = expression(value, "force", jet, rules);
    if (jet.highest_coordinate_order(q) > 1)
      fail(value,
           "a generalized force may depend on t, q and q' only (found a derivative of "
           "order " +
               std::to_string(jet.highest_coordinate_order(q)) + ")");
    scene.forces[static_cast<std::size_t>(*i)] = q;
  }
}

/// The identifiers of `text` that are among `names`, in order of appearance.
template <class Names>
std::vector<std::string> SceneReader::names_among(const std::string& text, const Names& names) {
  std::vector<std::string> found;
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (!(std::isalpha(c) || c == '_')) {
      ++i;
      continue;
    }
    std::size_t j = i;
    while (j < text.size() && (std::isalnum(static_cast<unsigned char>(text[j])) || text[j] == '_')) ++j;
    if (names.count(text.substr(i, j - i))) found.push_back(text.substr(i, j - i));
    i = j;
  }
  return found;
}

bool SceneReader::names_any_of(const std::string& text, const std::set<std::string>& names) {
  return !names_among(text, names).empty();
}

/// The value of the parameter `name` computed from others, as an expression of the parameters
/// of the equations (resolved on first use, in any order); nullopt when `name` is not one.
std::optional<Value> SceneReader::derived_parameter(const std::string& name, const JetSpace& jet) {
  const auto node = derived_nodes_.find(name);
  if (node == derived_nodes_.end()) return std::nullopt;
  if (const auto known = derived_values_.find(name); known != derived_values_.end())
    return Value::scalar(known->second);
  if (std::find(derived_chain_.begin(), derived_chain_.end(), name) != derived_chain_.end()) {
    std::string chain;
    for (auto it = std::find(derived_chain_.begin(), derived_chain_.end(), name); it != derived_chain_.end(); ++it)
      chain += *it + " -> ";
    fail(*node->second, "parameter '" + name + "' is computed from itself: " + chain + name);
  }
  derived_chain_.push_back(name);
  ExpressionRules rules;  // numbers, pi, e and parameters only
  rules.allow_coordinates = false;
  rules.allow_time = false;
  rules.definition = [this, &jet](const std::string& n) { return derived_parameter(n, jet); };
  const GiNaC::ex value = expression(*node->second, "parameter '" + name + "'", jet, rules);
  derived_chain_.pop_back();
  derived_values_[name] = value;
  derived_order_.push_back(name);
  return Value::scalar(value);
}

/// Resolves every parameter computed from others, checks that its value is a finite number
/// and makes it known to [initial] and [simulate] like a parameter.
void SceneReader::read_derived_parameters(Scene& scene) {
  // Leaves first, with an explicit stack: each is then parsed with what it uses resolved, so a
  // chain of any length recurses one level (as DefinitionTable does for [definitions]).
  std::map<std::string, int> state;  // 1 on the stack, 2 resolved
  for (const auto& entry : derived_nodes_) {
    std::vector<std::pair<std::string, std::vector<std::string>>> stack;
    const auto push = [&](const std::string& name) {
      state[name] = 1;
      stack.emplace_back(name, names_among(*derived_nodes_.at(name)->value<std::string>(), derived_nodes_));
    };
    if (state[entry.first] == 0) push(entry.first);
    while (!stack.empty()) {
      auto& [name, uses] = stack.back();
      if (uses.empty()) {
        state[name] = 2;
        const std::string done = name;
        stack.pop_back();
        derived_parameter(done, *scene.jet);
        continue;
      }
      const std::string next = uses.back();
      uses.pop_back();
      if (state[next] == 1) {
        std::string chain;
        auto it = std::find_if(stack.begin(), stack.end(), [&](const auto& e) { return e.first == next; });
        for (; it != stack.end(); ++it) chain += it->first + " -> ";
        fail(*derived_nodes_.at(stack.back().first),
             "parameter '" + stack.back().first + "' is computed from itself: " + chain + next);
      }
      if (state[next] == 0) push(next);
    }
  }
  for (const std::string& name : derived_order_) {
    const GiNaC::ex& value = derived_values_.at(name);
    scene.derived_parameters.push_back({name, value});
    const std::optional<double> v = finite_value(value, scene.parameter_substitution());
    if (!v) fail(*derived_nodes_.at(name), "parameter '" + name + "' is not a finite number at the parameters' values");
    constants_[name] = *v;
  }
}

}  // namespace nhc::scene_reading
