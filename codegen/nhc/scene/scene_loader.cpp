// Reads scene TOML files (toml++) into Scene, validating every key and expression.
// Each problem becomes an InputError with the file, line and column of the offending value.
// The tables are read by part: scene_system_reader.cpp, scene_experiment_reader.cpp (and
// scene_optimize_reader.cpp), scene_presentation_reader.cpp.
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

namespace nhc {

namespace scene_reading {

Scene SceneReader::read() {
  if (const std::optional<TextCharacter> c = control_character(text_))
    throw InputError({path_, c->line, c->column},
                     fmt::format("TOML syntax: control character U+{:04X} (TOML allows only tab and line ends; "
                                 "write it as an escape such as \\u{:04X} inside a string)",
                                 static_cast<unsigned char>(c->text[0]), static_cast<unsigned char>(c->text[0])));
  if (const std::optional<MisplacedCharacter> m = misplaced_non_ascii(text_)) {
    const TextCharacter& c = m->character;
    if (m->after_backslash)
      throw InputError({path_, c.line, c.column},
                       "TOML syntax: '" + printable(c.text) +
                           "' after a backslash in a multi-line string (the "
                           "TOML reader cannot take it there; write it as a \\u escape or start the line with ASCII)");
    throw InputError({path_, c.line, c.column}, "TOML syntax: '" + printable(c.text) +
                                                    "' outside a string or comment (names, numbers and "
                                                    "punctuation are ASCII; write it inside quotes or after #)");
  }
  toml::table root;
  try {
    root = toml::parse(text_, path_);
  } catch (const toml::parse_error& e) {
    throw InputError(at(e.source()), std::string("TOML syntax: ") + std::string(e.description()));
  }

  check_keys(root, {"name",       "coordinates", "lagrangian", "constraints", "dependent",  "models",
                    "parameters", "initial",     "simulate",   "reference",   "invariants", "definitions",
                    "forces",     "outputs",     "inputs",     "visual",      "events",     "contacts",
                    "controller",  // read by the sampled run (app/sampled_run.hpp)
                    "optimize"});

  Scene scene;
  scene.source_path = path_;
  const toml::node& name_node = require(root, "name", "top level");
  scene.name = string_value(name_node, "name");
  if (!is_valid_identifier(scene.name))
    fail(name_node, "invalid name '" + printable(scene.name) +
                        "': it must match [A-Za-z_][A-Za-z0-9_]* (at most 64 characters) "
                        "and not be a C++ keyword");

  // Names: coordinates, then parameters; all distinct.
  const toml::node& coords_node = require(root, "coordinates", "top level");
  const toml::array& coords = array_value(coords_node, "coordinates");
  if (coords.empty()) fail(coords_node, "'coordinates' is empty: a scene needs at least one");
  std::vector<std::string> coordinate_names;
  for (const toml::node& c : coords) {
    std::string n = string_value(c, "coordinates entry");
    check_variable_name(c, n, "coordinate");
    coordinate_names.push_back(n);
  }

  // [parameters]: numbers (or constant expressions such as "pi/8") are the parameters of the
  // equations; an expression that names other parameters ("mw*r^2/2") is computed from them.
  std::vector<std::string> parameter_names;
  std::vector<double> parameter_values;
  if (const toml::node* params_node = root.get("parameters")) {
    const toml::table& params = table_value(*params_node, "parameters");
    std::set<std::string> keys;
    for (auto&& [key, value] : params) keys.insert(std::string(key.str()));
    for (auto&& [key, value] : params) {
      const std::string n(key.str());
      check_variable_name_at(at(key.source()), n, "parameter");
      if (value.is_string() && names_any_of(*value.value<std::string>(), keys)) {
        derived_nodes_[n] = &value;
        continue;
      }
      parameter_names.push_back(n);
      parameter_values.push_back(number_value(value, "parameter '" + n + "'"));
    }
  }

  // Multipliers count = constraints count; read the constraint strings first.
  std::vector<const toml::node*> constraint_nodes;
  if (const toml::node* cn = root.get("constraints")) {
    scene.constraints_where = at(*cn);
    const toml::array& arr = array_value(*cn, "constraints");
    for (const toml::node& c : arr) {
      string_value(c, "constraints entry");
      constraint_nodes.push_back(&c);
    }
    if (constraint_nodes.size() >= coordinate_names.size() && !constraint_nodes.empty())
      fail(*cn, std::to_string(constraint_nodes.size()) + " constraints on " + std::to_string(coordinate_names.size()) +
                    " coordinates: there must be fewer constraints than coordinates");
  }

  // [inputs]: names now (the jet space holds their symbols), default signals once the
  // parameters are known.
  std::vector<std::string> input_names;
  std::vector<std::pair<const toml::node*, SourceLocation>> input_nodes;
  if (const toml::node* inputs_node = root.get("inputs")) {
    for (const auto& [key, value] : entries_in_file_order(*inputs_node, "inputs")) {  // the order of u
      const std::string n(key->str());
      check_variable_name_at(at(key->source()), n, "input");
      input_names.push_back(n);
      input_nodes.emplace_back(value, at(key->source()));
    }
  }

  scene.jet = std::make_shared<JetSpace>(coordinate_names, static_cast<int>(constraint_nodes.size()), parameter_names,
                                         input_names);
  scene.parameter_values = parameter_values;
  for (std::size_t i = 0; i < parameter_names.size(); ++i) constants_[parameter_names[i]] = parameter_values[i];
  const JetSpace& jet = *scene.jet;
  read_derived_parameters(scene);
  for (std::size_t k = 0; k < input_nodes.size(); ++k)
    scene.jet->set_input_location(static_cast<int>(k), input_nodes[k].second);
  read_initial(root, scene);
  const GiNaC::exmap initial_point = initial_point_of(scene);

  ExpressionRules plain;  // t, parameters, coordinates; no multipliers
  plain.definition = [this, &jet](const std::string& n) { return derived_parameter(n, jet); };
  plain.rotation_check.point = &initial_point;
  plain.rotation_check.euler_chains = &scene.euler_chains;  // singular where they are (value.hpp)
  plain.node_budget = std::make_shared<std::size_t>(kMaxSceneNodes);
  // A feedback law is written in place of its input's name. The laws may use the definitions,
  // so they are read after them; while they are read every input stays a symbol, so that a law
  // reaching another input through a definition is refused at the law whatever the order of
  // the entries (read_input_signals), and no definition keeps a symbol its law should replace.
  bool inputs_read = false;
  plain.input_law = [&scene, &inputs_read](int k) -> std::optional<GiNaC::ex> {
    if (!inputs_read) return std::nullopt;
    const SceneInput& input = scene.inputs[static_cast<std::size_t>(k)];
    if (!input.feedback) return std::nullopt;
    return input.law;
  };
  DefinitionTable definitions(jet, plain, options_.keep_definitions);
  scene.keep_definitions = options_.keep_definitions;
  read_definitions(root, definitions);  // resolved when first used
  const ExpressionRules mechanics = definitions.rules_with_definitions(plain);
  read_input_signals(input_nodes, scene, mechanics);
  inputs_read = true;
  const toml::node& lagrangian_node = require(root, "lagrangian", "top level");
  scene.lagrangian = expression(lagrangian_node, "lagrangian", jet, mechanics);
  scene.lagrangian_where = at(lagrangian_node);
  if (jet.highest_coordinate_order(scene.lagrangian) > 1)
    fail(lagrangian_node,
         "the Lagrangian may depend on t, q and q' only (found a derivative "
         "of order " +
             std::to_string(jet.highest_coordinate_order(scene.lagrangian)) + ")");

  for (std::size_t a = 0; a < constraint_nodes.size(); ++a) {
    const toml::node& c = *constraint_nodes[a];
    GiNaC::ex f = expression(c, "constraint", jet, mechanics);
    if (is_zero_at(c, f) || vanishes_at_sample_points(f))  // sin(x)^2 + cos(x)^2 - 1 too
      fail(c, "constraint " + std::to_string(a + 1) + " is identically zero");
    if (jet.highest_coordinate_order(f) < 0)
      fail(c, "constraint " + std::to_string(a + 1) + " does not involve any coordinate");
    scene.constraints.push_back(f);
    scene.constraint_texts.push_back(*c.value<std::string>());
  }

  if (const toml::node* dn = root.get("dependent")) {
    const toml::array& arr = array_value(*dn, "dependent");
    std::set<int> seen;
    for (const toml::node& d : arr) {
      const std::string n = string_value(d, "dependent entry");
      const std::optional<int> found = scene.jet->coordinate_index(n);
      if (!found) fail(d, "'" + printable(n) + "' is not a coordinate");
      const int index = *found;
      if (!seen.insert(index).second) fail(d, "dependent coordinate '" + n + "' listed twice");
      scene.dependent.push_back(index);
    }
    if (scene.dependent.size() != scene.constraints.size())
      fail(*dn, "'dependent' lists " + std::to_string(scene.dependent.size()) + " coordinates but there are " +
                    std::to_string(scene.constraints.size()) +
                    " constraints; give one dependent coordinate per constraint");
  }

  if (const toml::node* mn = root.get("models")) {
    const toml::array& arr = array_value(*mn, "models");
    if (arr.empty()) fail(*mn, "'models' is empty");
    for (const toml::node& m : arr) {
      const std::string n = string_value(m, "models entry");
      auto kind = parse_model_kind(n);
      if (!kind) fail(m, "unknown model '" + printable(n) + "' (known: " + model_name_list() + ")");
      if (std::find(scene.models.begin(), scene.models.end(), *kind) != scene.models.end())
        fail(m, "model '" + n + "' listed twice");
      scene.models.push_back(*kind);
      scene.models_where[*kind] = at(m);
    }
  } else {
    scene.models.assign(std::begin(kAllModels), std::end(kAllModels));
  }

  read_simulate(root, scene);

  if (const toml::node* rn = root.get("reference")) read_reference(*rn, scene, mechanics);
  if (const toml::node* in = root.get("invariants"))
    scene.invariants = read_quantities(*in, "invariants", "invariant", *scene.jet, multipliers_allowed(mechanics));
  read_outputs(root, scene, mechanics);
  read_events(root, scene, mechanics);
  read_contacts(root, scene, mechanics);
  read_forces(root, scene, mechanics);
  read_visuals(root, scene, mechanics);
  read_controller(root, scene, mechanics);
  // [optimize]'s objective and final cost may use the definitions: read before the unused ones are named.
  scene_reading::read_optimize(root, scene, path_, mechanics);
  definitions.resolve_all();
  for (const auto& [name, where] : definitions.unused())
    scene.warnings.push_back(where.str() + ": warning: definition '" + name + "' is never used");
  return scene;
}

}  // namespace scene_reading

using scene_reading::SceneReader;

Scene parse_scene(const std::string& text, const std::string& path, const SceneOptions& options) {
  work_budget::set_scene_path(path);  // the work budget's refusal names it (also for nhc.Scene.from_toml)
  Scene scene = SceneReader(text, path, options).read();
  scene.set_source_text(text);
  return scene;
}

Scene load_scene(const std::string& path, const SceneOptions& options) {
  const std::string text = read_input_file(path, "a scene file");
  work_budget::set_scene_path(path);
  const work_budget::Stage stage("reading the scene");
  Scene scene = parse_scene(text, path, options);
  for (const std::string& warning : scene.warnings) std::cerr << warning << "\n";
  return scene;
}

}  // namespace nhc
