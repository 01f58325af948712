// Reads scene TOML files (toml++) into Scene, validating every key and expression.
// Each problem becomes an InputError with the file, line and column of the offending value.
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
#include "nhc/runtime/number_text.hpp"
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

bool is_cpp_keyword(const std::string& name) {
  static const std::set<std::string> keywords = {
      "alignas", "alignof", "and", "and_eq", "asm", "auto", "bitand", "bitor", "bool", "break",
      "case", "catch", "char", "char8_t", "char16_t", "char32_t", "class", "compl", "concept",
      "const", "consteval", "constexpr", "constinit", "const_cast", "continue", "co_await",
      "co_return", "co_yield", "decltype", "default", "delete", "do", "double", "dynamic_cast",
      "else", "enum", "explicit", "export", "extern", "false", "float", "for", "friend", "goto",
      "if", "inline", "int", "long", "mutable", "namespace", "new", "noexcept", "not", "not_eq",
      "nullptr", "operator", "or", "or_eq", "private", "protected", "public", "register",
      "reinterpret_cast", "requires", "return", "short", "signed", "sizeof", "static",
      "static_assert", "static_cast", "struct", "switch", "template", "this", "thread_local",
      "throw", "true", "try", "typedef", "typeid", "typename", "union", "unsigned", "using",
      "virtual", "void", "volatile", "wchar_t", "while", "xor", "xor_eq"};
  return keywords.count(name) > 0;
}

bool is_valid_identifier(const std::string& name) {
  if (name.empty() || name.size() > 64) return false;
  const auto c0 = static_cast<unsigned char>(name[0]);
  if (!(std::isalpha(c0) || name[0] == '_')) return false;
  for (char c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (!(std::isalnum(u) || c == '_') || u >= 0x80) return false;
  }
  return !is_cpp_keyword(name);
}

GiNaC::exmap Scene::parameter_substitution() const {
  GiNaC::exmap m;
  for (std::size_t p = 0; p < parameter_values.size(); ++p)
    m[jet->parameter(static_cast<int>(p))] = parameter_values[p];
  return m;
}

GiNaC::exmap Scene::input_substitution(double t) const {
  GiNaC::exmap values = parameter_substitution();
  values[jet->time()] = t;
  GiNaC::exmap m;
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    const GiNaC::ex u = GiNaC::evalf(inputs[k].default_signal.subs(values, GiNaC::subs_options::no_pattern));
    if (!GiNaC::is_a<GiNaC::numeric>(u) || !GiNaC::ex_to<GiNaC::numeric>(u).is_real() ||
        !std::isfinite(GiNaC::ex_to<GiNaC::numeric>(u).to_double()))
      throw MathError("input '" + inputs[k].name + "' is not a finite number at t = " + std::to_string(t));
    m[jet->input(static_cast<int>(k))] = GiNaC::ex_to<GiNaC::numeric>(u).to_double();
  }
  return m;
}

SceneReference::Entries SceneReference::for_model(ModelKind model) const {
  Entries entries = all;
  if (const auto it = per_model.find(model); it != per_model.end()) {
    for (const auto& entry : it->second) {
      const auto same = std::find_if(entries.begin(), entries.end(),
                                     [&](const auto& e) { return e.first == entry.first; });
      if (same != entries.end())
        same->second = entry.second;
      else
        entries.push_back(entry);
    }
  }
  std::stable_sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return entries;
}

std::optional<double> finite_value(const GiNaC::ex& e, const GiNaC::exmap& values) {
  try {
    const GiNaC::ex v = GiNaC::evalf(e.subs(values, GiNaC::subs_options::no_pattern));
    if (!GiNaC::is_a<GiNaC::numeric>(v) || !GiNaC::ex_to<GiNaC::numeric>(v).is_real()) return std::nullopt;
    const double d = GiNaC::ex_to<GiNaC::numeric>(v).to_double();
    if (!std::isfinite(d)) return std::nullopt;
    return d;
  } catch (const std::exception&) {
    return std::nullopt;  // 1/0, log(0): not a number
  }
}

std::map<std::string, double> Scene::parameter_values_by_name() const {
  std::map<std::string, double> names;
  for (std::size_t p = 0; p < parameter_values.size(); ++p) names[jet->parameters()[p]] = parameter_values[p];
  const GiNaC::exmap values = parameter_substitution();
  for (const DerivedParameter& d : derived_parameters)
    if (const std::optional<double> v = finite_value(d.value, values)) names[d.name] = *v;
  return names;
}

const DerivedParameter* Scene::derived_parameter(const std::string& name) const {
  for (const DerivedParameter& d : derived_parameters)
    if (d.name == name) return &d;
  return nullptr;
}

void reevaluate_initial_expressions(Scene& scene) {
  const std::map<std::string, double> names = scene.parameter_values_by_name();
  for (const auto& [name, texts] : scene.initial.expressions) {
    std::vector<double>& values = scene.initial.values[name];
    for (std::size_t k = 0; k < texts.size() && k < values.size(); ++k)
      if (!texts[k].empty()) values[k] = evaluate_constant_expression(texts[k], names);  // checked when read
  }
}

namespace scene_reading {

/// Non-printable bytes are shown as \xNN so that the one-line message stays one line; a
/// long text is cut after 60 bytes (at a character boundary) and marked with "...".
std::string printable(const std::string& text) {
  constexpr std::size_t kShown = 60;
  std::string s = text;
  if (s.size() > kShown) {
    std::size_t cut = kShown;
    while (cut > 0 && (static_cast<unsigned char>(s[cut]) & 0xc0) == 0x80) --cut;
    s = s.substr(0, cut) + "...";
  }
  std::string out;
  for (unsigned char c : s) {
    if (c < 0x20 || c == 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", c);
      out += buf;
    } else {
      out += static_cast<char>(c);
    }
  }
  return out;
}

}  // namespace scene_reading

namespace {

using scene_reading::printable;

bool is_function_name(const std::string& name) {
  const auto& names = function_names();
  return std::find(names.begin(), names.end(), name) != names.end();
}

bool looks_like_multiplier(const std::string& name) {
  if (name.rfind("lambda", 0) != 0 || name.size() == 6) return false;
  return std::all_of(name.begin() + 6, name.end(),
                     [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
}

bool has_jet_suffix(const std::string& name) {
  const auto pos = name.rfind("_d");
  if (pos == std::string::npos || pos == 0 || pos + 2 >= name.size()) return false;
  return std::all_of(name.begin() + static_cast<long>(pos) + 2, name.end(),
                     [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
}

class SceneReader {
 public:
  SceneReader(const std::string& text, std::string path, SceneOptions options)
      : text_(text), path_(std::move(path)), options_(options) {
    std::istringstream lines(text_);
    for (std::string line; std::getline(lines, line);) lines_.push_back(line);
  }

  Scene read() {
    if (const std::optional<TextCharacter> c = control_character(text_))
      throw InputError({path_, c->line, c->column},
                       fmt::format("TOML syntax: control character U+{:04X} (TOML allows only tab and line ends; "
                                   "write it as an escape such as \\u{:04X} inside a string)",
                                   static_cast<unsigned char>(c->text[0]), static_cast<unsigned char>(c->text[0])));
    if (const std::optional<MisplacedCharacter> m = misplaced_non_ascii(text_)) {
      const TextCharacter& c = m->character;
      if (m->after_backslash)
        throw InputError({path_, c.line, c.column},
                         "TOML syntax: '" + printable(c.text) + "' after a backslash in a multi-line string (the "
                         "TOML reader cannot take it there; write it as a \\u escape or start the line with ASCII)");
      throw InputError({path_, c.line, c.column},
                       "TOML syntax: '" + printable(c.text) + "' outside a string or comment (names, numbers and "
                       "punctuation are ASCII; write it inside quotes or after #)");
    }
    toml::table root;
    try {
      root = toml::parse(text_, path_);
    } catch (const toml::parse_error& e) {
      throw InputError(at(e.source()), std::string("TOML syntax: ") + std::string(e.description()));
    }

    check_keys(root, {"name", "coordinates", "lagrangian", "constraints", "dependent", "models",
                      "parameters", "initial", "simulate", "reference", "invariants",
                      "definitions", "forces", "outputs", "inputs", "visual", "events", "contacts",
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
        fail(*cn, std::to_string(constraint_nodes.size()) + " constraints on " +
                      std::to_string(coordinate_names.size()) +
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

    scene.jet = std::make_shared<JetSpace>(coordinate_names,
                                           static_cast<int>(constraint_nodes.size()),
                                           parameter_names, input_names);
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
      fail(lagrangian_node, "the Lagrangian may depend on t, q and q' only (found a derivative "
                            "of order " +
                                std::to_string(jet.highest_coordinate_order(scene.lagrangian)) +
                                ")");

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
        fail(*dn, "'dependent' lists " + std::to_string(scene.dependent.size()) +
                      " coordinates but there are " + std::to_string(scene.constraints.size()) +
                      " constraints; give one dependent coordinate per constraint");
    }

    if (const toml::node* mn = root.get("models")) {
      const toml::array& arr = array_value(*mn, "models");
      if (arr.empty()) fail(*mn, "'models' is empty");
      for (const toml::node& m : arr) {
        const std::string n = string_value(m, "models entry");
        auto kind = parse_model_kind(n);
        if (!kind)
          fail(m, "unknown model '" + printable(n) + "' (known: " + model_name_list() + ")");
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
    definitions.resolve_all();
    for (const auto& [name, where] : definitions.unused())
      scene.warnings.push_back(where.str() + ": warning: definition '" + name + "' is never used");
    scene_reading::read_optimize(root, scene, path_);
    return scene;
  }

 private:
  SourceLocation at(const toml::source_region& region) const {
    return {path_, static_cast<int>(region.begin.line), static_cast<int>(region.begin.column)};
  }
  SourceLocation at(const toml::node& node) const { return at(node.source()); }

  [[noreturn]] void fail(const toml::node& node, const std::string& message) const {
    throw InputError(at(node), message);
  }

  /// A number as written (0, 1.5, 1e-08), not std::to_string's 0.000000.
  static std::string shortest(double v) {
    const std::string shorter = runtime::number_text(v, 6);  // enough unless that loses the value
    return std::stod(shorter) == v ? shorter : runtime::number_text(v, 17);
  }

  void check_keys(const toml::table& table, const std::set<std::string>& allowed) const {
    for (auto&& [key, value] : table) {
      const std::string k(key.str());
      if (!allowed.count(k)) {
        std::string list;
        for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
        throw InputError(at(key.source()),
                         "unknown key '" + printable(k) + "' (expected one of: " + list + ")");
      }
    }
  }

  const toml::node& require(const toml::table& table, const std::string& key,
                            const std::string& where) const {
    const toml::node* n = table.get(key);
    if (!n) {
      SourceLocation loc = at(table);
      if (loc.line <= 0) loc = {path_, 1, 1};
      throw InputError(loc, "missing required key '" + key + "' (" + where + ")");
    }
    return *n;
  }

  std::string string_value(const toml::node& node, const std::string& what) const {
    if (!node.is_string()) fail(node, what + " must be a string, not " + type_name(node));
    return *node.value<std::string>();
  }
  const toml::array& array_value(const toml::node& node, const std::string& what) const {
    if (!node.is_array()) fail(node, "'" + what + "' must be an array, not " + type_name(node));
    return *node.as_array();
  }
  const toml::table& table_value(const toml::node& node, const std::string& what) const {
    if (!node.is_table()) fail(node, "'" + what + "' must be a table, not " + type_name(node));
    return *node.as_table();
  }
  double number_value(const toml::node& node, const std::string& what) const {
    double v = 0;
    if (node.is_integer()) v = static_cast<double>(*node.value<int64_t>());
    else if (node.is_floating_point()) v = *node.value<double>();
    else if (node.is_string()) v = constant_value(node, what);  // "pi/8", "v*cos(pi/6)"
    else fail(node, what + " must be a number, not " + type_name(node));
    if (!std::isfinite(v)) fail(node, what + " must be finite");
    return v;
  }
  static std::string type_name(const toml::node& node) {
    switch (node.type()) {
      case toml::node_type::table: return "a table";
      case toml::node_type::array: return "an array";
      case toml::node_type::string: return "a string";
      case toml::node_type::integer: return "an integer";
      case toml::node_type::floating_point: return "a floating-point number";
      case toml::node_type::boolean: return "a boolean";
      default: return "a date or time";
    }
  }

  void check_variable_name(const toml::node& node, const std::string& n,
                           const std::string& what) {
    check_variable_name_at(at(node), n, what);
  }
  void check_variable_name_at(const SourceLocation& where, const std::string& n,
                              const std::string& what) {
    auto bad = [&](const std::string& why) {
      throw InputError(where, "invalid " + what + " name '" + printable(n) + "': " + why);
    };
    if (!is_valid_identifier(n))
      bad("it must match [A-Za-z_][A-Za-z0-9_]* (at most 64 characters) and not be a C++ keyword");
    if (n == "t") bad("'t' is time");
    if (n == "Pi") bad("'Pi' is the constant pi in expressions");
    if (looks_like_multiplier(n)) bad("lambda<N> names are reserved for the multipliers");
    if (is_function_name(n)) bad("it is the name of a function");
    if (has_jet_suffix(n)) bad("names ending in _d<digits> are reserved for derivatives");
    if (!names_.insert(n).second) bad("the name is used twice");
  }

  /// Column of character `offset` of a string value, when the value is a one-line string
  /// without escapes (then columns map one to one); else the value's start.
  SourceLocation expression_location(const toml::node& node, std::size_t offset) const {
    SourceLocation loc = at(node);
    const std::string value = *node.value<std::string>();
    if (loc.line <= 0 || static_cast<std::size_t>(loc.line) > lines_.size()) return loc;
    const std::string& line = lines_[static_cast<std::size_t>(loc.line - 1)];
    const std::size_t start = static_cast<std::size_t>(loc.column - 1);
    if (start >= line.size() || (line[start] != '"' && line[start] != '\'')) return loc;
    if (line.compare(start + 1, value.size(), value) != 0) return loc;
    loc.column += static_cast<int>(1 + std::min(offset, value.size()));
    return loc;
  }

  GiNaC::ex expression(const toml::node& node, const std::string& what, const JetSpace& jet,
                       const ExpressionRules& rules) const {
    const std::string text = string_value(node, what);
    try {
      return parse_expression(text, jet, rules);
    } catch (const ExpressionSyntaxError& e) {
      throw InputError(expression_location(node, e.offset()),
                       "in " + what + " \"" + printable(text) + "\": " + e.what());
    }
  }

  /// work_budget::is_zero(e) for the expression of `node`, a refusal located there.
  bool is_zero_at(const toml::node& node, const GiNaC::ex& e) const {
    try {
      return work_budget::is_zero(e);
    } catch (const WorkLimitExceeded& error) {
      throw error.located(at(node), "checking this expression");
    }
  }

  /// [definitions]: name = "expression", names checked like parameters, resolved on use.
  void read_definitions(const toml::table& root, DefinitionTable& definitions) {
    const toml::node* node = root.get("definitions");
    if (!node) return;
    for (auto&& [key, value] : table_value(*node, "definitions")) {
      const std::string n(key.str());
      check_variable_name_at(at(key.source()), n, "definition");
      const std::string text = string_value(value, "definition '" + n + "'");
      const toml::node* value_node = &value;
      definitions.add(n, text, [this, value_node](std::size_t offset) {
        return expression_location(*value_node, offset);
      });
    }
  }

  /// [outputs]: name = "expression" of t, parameters, coordinates, their derivatives and the
  /// multipliers; written as CSV columns by nhc simulate, never checked for drift.
  static ExpressionRules multipliers_allowed(ExpressionRules rules) {
    rules.allow_multipliers = true;
    return rules;
  }

  void read_outputs(const toml::table& root, Scene& scene, const ExpressionRules& rules) {
    if (const toml::node* node = root.get("outputs"))
      scene.outputs = read_quantities(*node, "outputs", "output", *scene.jet, multipliers_allowed(rules));
  }

  /// [events]: name = { when = "expression", direction = "up"|"down"|"any", action =
  /// "stop"|"record" } (docs/scenes.md); the expression may use what [outputs] may.
  void read_events(const toml::table& root, Scene& scene, const ExpressionRules& rules) {
    const toml::node* node = root.get("events");
    if (!node) return;
    for (const auto& [key, value] : entries_in_file_order(*node, "events")) {
      const std::string n(key->str());
      check_variable_name_at(at(key->source()), n, "event");
      const toml::table* t = value->as_table();
      if (!t) fail(*value, "event '" + n + "' must be a table: { when = \"expression\", direction = \"up\", action = \"stop\" }");
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
  void read_contacts(const toml::table& root, Scene& scene, const ExpressionRules& rules) {
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
      contact.normal = expression(normal, "the normal force of contact '" + n + "'", *scene.jet,
                                  multipliers_allowed(rules));
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

  /// The entries of a table in the order the file writes them (toml++ keeps tables sorted by key).
  std::vector<std::pair<const toml::key*, const toml::node*>> entries_in_file_order(const toml::node& node,
                                                                                    const std::string& table) const {
    std::vector<std::pair<const toml::key*, const toml::node*>> entries;
    for (auto&& [key, value] : table_value(node, table)) entries.emplace_back(&key, &value);
    std::sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) {
      const toml::source_position pa = a.first->source().begin, pb = b.first->source().begin;
      return pa.line != pb.line ? pa.line < pb.line : pa.column < pb.column;
    });
    return entries;
  }

  /// [invariants] and [outputs]: name = "expression", or name = { expression = "…", required =
  /// true } for an entry every model must compute; in file order (the CSV's).
  std::vector<SceneQuantity> read_quantities(const toml::node& node, const std::string& table, const std::string& what,
                                             const JetSpace& jet, const ExpressionRules& rules) {
    std::vector<SceneQuantity> quantities;
    for (const auto& [key, value] : entries_in_file_order(node, table)) {
      const std::string n(key->str());
      check_variable_name_at(at(key->source()), n, what);
      const toml::node* text = value;
      bool required = false;
      if (const toml::table* t = value->as_table()) {
        check_keys(*t, {"expression", "required"});
        text = &require(*t, "expression", table + "." + n);
        if (const toml::node* r = t->get("required")) {
          if (!r->is_boolean()) fail(*r, "required must be true or false");
          required = r->as_boolean()->get();
        }
      }
      quantities.push_back({n, expression(*text, what + " '" + n + "'", jet, rules), at(*text), required});
    }
    return quantities;
  }

  /// A value of the scene language (value.hpp) written at `node`: a string, a number (a scalar)
  /// or an array of numbers and strings (a vector).
  Value value_at(const toml::node& node, const std::string& what, const JetSpace& jet, const ExpressionRules& rules) {
    if (node.is_number()) return Value::scalar(GiNaC::ex(number_value(node, what)));
    if (const toml::array* entries = node.as_array()) {
      std::vector<GiNaC::ex> vector;
      for (const toml::node& entry : *entries)
        vector.push_back(entry.is_string() ? expression(entry, what, jet, rules) : GiNaC::ex(number_value(entry, what)));
      if (vector.size() < 2) fail(node, what + " must have at least two entries");
      return Value::vector(std::move(vector));
    }
    const std::string text = string_value(node, what);
    try {
      return parse_value(text, jet, rules);
    } catch (const ExpressionSyntaxError& e) {
      throw InputError(expression_location(node, e.offset()), "in " + what + " \"" + printable(text) + "\": " + e.what());
    }
  }

  /// [visual]: name = { shape = "sphere", radius = "r", center = "c", … } (scene_visual.hpp),
  /// each value checked for its kind: a scalar, a 3-vector, a rotation (R Rᵀ = I
  /// symbolically, else at the initial point).
  void read_visuals(const toml::table& root, Scene& scene, const ExpressionRules& rules) {
    const toml::node* node = root.get("visual");
    if (!node) return;
    for (const auto& [key, value] : entries_in_file_order(*node, "visual")) {
      const std::string n(key->str());
      if (!is_valid_identifier(n))
        throw InputError(at(key->source()), "invalid visual name '" + printable(n) +
                                                "': it must match [A-Za-z_][A-Za-z0-9_]* (at most 64 characters)");
      const std::string what = "visual '" + n + "'";
      const toml::table& table = table_value(*value, what);
      SceneVisual visual;
      visual.name = n;
      visual.where = at(key->source());
      const std::string shape_name = string_value(require(table, "shape", what), what + " shape");
      const std::optional<VisualShape> shape = parse_visual_shape(shape_name);
      if (!shape)
        fail(*table.get("shape"), "unknown shape '" + printable(shape_name) + "' (known: " + visual_shape_names() + ")");
      visual.shape = *shape;
      std::set<std::string> allowed{"shape", "color", "opacity"};
      for (const VisualKey& k : visual_keys(visual.shape)) allowed.insert(k.name);
      if (visual.shape == VisualShape::cylinder) allowed.insert("axis");
      check_keys(table, allowed);
      for (const VisualKey& k : visual_keys(visual.shape)) {
        const toml::node* entry = table.get(k.name);
        if (!entry) {
          if (k.required) require(table, k.name, what + ", shape " + shape_name);
          continue;
        }
        const std::string entry_what = what + " " + k.name;
        const Value v = value_at(*entry, entry_what, *scene.jet, rules);
        check_visual_value(*entry, entry_what, k.kind, v, rules);
        visual.values.emplace(k.name, v);
        visual.value_where.emplace(k.name, at(*entry));
      }
      if (const toml::node* axis = table.get("axis")) {
        const std::string a = string_value(*axis, what + " axis");
        if (a != "x" && a != "y" && a != "z") fail(*axis, what + " axis must be \"x\", \"y\" or \"z\"");
        visual.axis = a[0] - 'x';
      }
      if (const toml::node* color = table.get("color")) visual.color = color_value(*color, what + " color");
      if (const toml::node* opacity = table.get("opacity")) {
        visual.opacity = number_value(*opacity, what + " opacity");
        if (!(visual.opacity >= 0 && visual.opacity <= 1)) fail(*opacity, what + " opacity must be between 0 and 1");
      }
      scene.visuals.push_back(std::move(visual));
    }
  }

  void check_visual_value(const toml::node& node, const std::string& what, VisualValueKind kind, const Value& v,
                          const ExpressionRules& rules) const {
    switch (kind) {
      case VisualValueKind::scalar:
        if (!v.is_scalar()) fail(node, what + " must be a scalar, got " + v.describe());
        break;
      case VisualValueKind::vector:
        if (!(v.rows == 3 && v.cols == 1)) fail(node, what + " must be a 3-vector, got " + v.describe());
        break;
      case VisualValueKind::rotation:
        if (!v.is_square3()) fail(node, what + " must be a 3x3 rotation matrix, got " + v.describe());
        if (!v.angular_velocity) {  // not built from rotx/roty/rotz: check R Rᵀ = I
          try {
            require_rotation(v, rules.rotation_check, what.c_str());
          } catch (const ValueError& e) {
            fail(node, e.what());
          }
        }
        break;
    }
  }

  /// "#rgb" or "#rrggbb", as "#rrggbb".
  std::string color_value(const toml::node& node, const std::string& what) const {
    const std::string c = string_value(node, what);
    const bool hex = c.size() > 1 && c[0] == '#' &&
                     std::all_of(c.begin() + 1, c.end(), [](unsigned char ch) { return std::isxdigit(ch) != 0; });
    if (!hex || (c.size() != 4 && c.size() != 7))
      fail(node, what + " must be \"#rrggbb\" or \"#rgb\" (hexadecimal), not \"" + printable(c) + "\"");
    if (c.size() == 7) return c;
    return std::string{'#', c[1], c[1], c[2], c[2], c[3], c[3]};
  }

  /// [reference]: coordinate = "q(t)" for every model; [reference.<model>] for one model.
  void read_reference(const toml::node& node, Scene& scene, const ExpressionRules& mechanics) {
    ExpressionRules time_only = mechanics;
    time_only.allow_coordinates = false;
    const auto read_entries = [&](const toml::table& table, const std::string& where) {
      SceneReference::Entries entries;
      for (auto&& [key, value] : table) {
        const std::string n(key.str());
        if (value.is_table()) {
          const auto kind = parse_model_kind(n);
          if (!kind || where != "reference")
            throw InputError(at(key.source()),
                             "[" + where + "." + printable(n) + "]: " +
                                 (where != "reference" ? "a model's reference holds coordinates only"
                                                       : "'" + printable(n) + "' is not a model (known: " + model_name_list() + ")"));
          continue;
        }
        const std::optional<int> i = scene.jet->coordinate_index(n);
        if (!i)
          throw InputError(at(key.source()),
                           "[" + where + "] names '" + printable(n) + "', which is not a coordinate");
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
  void read_input_signals(const std::vector<std::pair<const toml::node*, SourceLocation>>& nodes, Scene& scene,
                          const ExpressionRules& rules) {
    ExpressionRules signal = rules;
    signal.allow_inputs = false;  // a signal of t, or a feedback law of t, q and q'; no other input
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      const toml::node& value = *nodes[k].first;
      const std::string& name = scene.jet->inputs()[k];
      GiNaC::ex u;
      if (value.is_number()) u = number_value(value, "input '" + name + "'");
      else if (value.is_string()) u = expression(value, "input '" + name + "'", *scene.jet, signal);
      else fail(value, "input '" + name + "' must be a number or an expression of t, the parameters and the coordinates (a string)");
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

  /// [controller]: period = h > 0, states = { z = value }, inputs = { U = "law" } (each an
  /// [inputs] entry without a law of its own), update = { z = "next value" } (one per state).
  /// The expressions may use what a feedback law may, the states, and `period` (docs/scenes.md).
  void read_controller(const toml::table& root, Scene& scene, const ExpressionRules& rules) {
    const toml::node* node = root.get("controller");
    if (!node) return;
    const toml::table& table = table_value(*node, "controller");
    check_keys(table, {"period", "states", "inputs", "update"});
    SceneController& controller = scene.controller;
    controller.present = true;
    controller.where = at(*node);
    if (controller.where.line <= 0) controller.where = scene.file_location();
    const toml::node& period = require(table, "period", "controller");
    controller.period = number_value(period, "period");
    controller.period_where = at(period);
    if (!(controller.period > 0)) fail(period, "period must be a positive number (the controller's sample period h)");
    const JetSpace& jet = *scene.jet;
    std::map<std::string, int> state_index;
    if (const toml::node* states = table.get("states")) {
      for (const auto& [key, value] : entries_in_file_order(*states, "controller.states")) {
        const std::string n(key->str());
        if (jet.coordinate_index(n))
          throw InputError(at(key->source()), "controller state '" + printable(n) +
                                                  "' is named like a coordinate: a discrete state needs a name of its own");
        if (n == "period") throw InputError(at(key->source()), "'period' is the controller's sample period, not a state name");
        check_variable_name_at(at(key->source()), n, "controller state");
        SceneControllerState state{n, number_value(*value, "controller state '" + n + "'"), GiNaC::symbol(n), at(key->source())};
        state_index[n] = static_cast<int>(controller.states.size());
        controller.states.push_back(state);
      }
    }
    // The states and `period` are names of the controller's expressions; the rest is the scene's.
    ExpressionRules law = rules;
    law.allow_multipliers = false;
    law.allow_inputs = false;  // the controller sets inputs; it does not read them
    law.input_law = nullptr;
    const GiNaC::ex h = GiNaC::numeric(controller.period);
    law.definition = [&controller, state_index, h, outer = rules.definition](const std::string& name) -> std::optional<Value> {
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
          throw InputError(at(key->source()), "[controller] sets input '" + n + "', whose [inputs] entry is a feedback law (" +
                                                  input.where.str() + "): an input has one law; give it a signal there");
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
      controller.update.push_back(read_law(*updates[i], static_cast<int>(i), state.name, "update of '" + state.name + "'"));
    }
  }

  void read_forces(const toml::table& root, Scene& scene, const ExpressionRules& rules) {
    const JetSpace& jet = *scene.jet;
    scene.forces.assign(static_cast<std::size_t>(jet.coordinate_count()), GiNaC::ex(0));
    const toml::node* node = root.get("forces");
    if (!node) return;
    for (auto&& [key, value] : table_value(*node, "forces")) {
      const std::string n(key.str());
      const std::optional<int> i = jet.coordinate_index(n);
      if (!i)
        throw InputError(at(key.source()),
                         "[forces] names '" + printable(n) + "', which is not a coordinate");
      const GiNaC::ex q = expression(value, "force", jet, rules);
      if (jet.highest_coordinate_order(q) > 1)
        fail(value, "a generalized force may depend on t, q and q' only (found a derivative of "
                    "order " + std::to_string(jet.highest_coordinate_order(q)) + ")");
      scene.forces[static_cast<std::size_t>(*i)] = q;
    }
  }

  /// Parameters and given initial values q_i^(k)(t0): where omega() checks a matrix numerically.
  static GiNaC::exmap initial_point_of(const Scene& scene) {
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

  void read_initial(const toml::table& root, Scene& scene) {
    const toml::node* node = root.get("initial");
    if (!node) return;
    const toml::table& table = table_value(*node, "initial");
    const JetSpace& jet = *scene.jet;
    for (auto&& [key, value] : table) {
      const std::string n(key.str());
      if (n == "t0") {
        scene.initial.t0 = number_value(value, "initial t0");
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
        fail(value, "initial values of '" + n + "' go beyond derivative order " +
                        std::to_string(kMaxDerivativeOrder));
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
  void check_fixed(Scene& scene) {
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

  void read_simulate(const toml::table& root, Scene& scene) {
    const toml::node* node = root.get("simulate");
    if (!node) {
      scene.simulate.t_end = scene.initial.t0 + 1.0;
      return;
    }
    const toml::table& table = table_value(*node, "simulate");
    check_keys(table, {"model", "t_end", "rtol", "atol", "outputs"});
    scene.simulate.t_end = scene.initial.t0 + 1.0;
    if (const toml::node* m = table.get("model")) {
      const std::string n = string_value(*m, "simulate model");
      auto kind = parse_model_kind(n);
      if (!kind)
        fail(*m, "unknown model '" + printable(n) + "' (known: " + model_name_list() + ")");
      if (std::find(scene.models.begin(), scene.models.end(), *kind) == scene.models.end())
        fail(*m, "model '" + n + "' is not among the scene's models");
      scene.simulate.model = kind;
    }
    if (const toml::node* te = table.get("t_end")) {
      scene.simulate.t_end = number_value(*te, "t_end");
      if (!(scene.simulate.t_end > scene.initial.t0))
        fail(*te, "t_end must be after t0 = " + shortest(scene.initial.t0));
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
      }
    }
  }

  /// The identifiers of `text` that are among `names`, in order of appearance.
  template <class Names>
  static std::vector<std::string> names_among(const std::string& text, const Names& names) {
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
  static bool names_any_of(const std::string& text, const std::set<std::string>& names) {
    return !names_among(text, names).empty();
  }

  /// The value of the parameter `name` computed from others, as an expression of the parameters
  /// of the equations (resolved on first use, in any order); nullopt when `name` is not one.
  std::optional<Value> derived_parameter(const std::string& name, const JetSpace& jet) {
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
  void read_derived_parameters(Scene& scene) {
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
          fail(*derived_nodes_.at(stack.back().first), "parameter '" + stack.back().first +
                                                           "' is computed from itself: " + chain + next);
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

  /// A constant expression (constant_expression.hpp) over pi, e and the parameters read so far.
  double constant_value(const toml::node& node, const std::string& what) const {
    try {
      return evaluate_constant_expression(*node.value<std::string>(), constants_);
    } catch (const std::invalid_argument& e) {
      fail(node, what + ": " + e.what());
    }
  }

  const std::string& text_;
  std::string path_;
  SceneOptions options_;
  std::map<std::string, double> constants_;  ///< the parameters, once read
  std::map<std::string, const toml::node*> derived_nodes_;  ///< [parameters] computed from others
  std::map<std::string, GiNaC::ex> derived_values_;         ///< … as expressions of the parameters
  std::vector<std::string> derived_order_;                  ///< … each after those it uses
  std::vector<std::string> derived_chain_;                  ///< being resolved (for cycles)
  std::vector<const toml::node*> fixed_nodes_;  ///< [initial] fixed, checked after the values
  std::vector<std::string> lines_;
  std::set<std::string> names_;
};

}  // namespace

Scene parse_scene(const std::string& text, const std::string& path, const SceneOptions& options) {
  work_budget::set_scene_path(path);  // the work budget's refusal names it (also for nhc.Scene.from_toml)
  Scene scene = SceneReader(text, path, options).read();
  scene.set_source_text(text);
  return scene;
}

std::string switched_source(const std::string& text, const std::set<int>& removed,
                            const std::map<std::string, std::string>& added_forces) {
  toml::table root;
  try {
    root = toml::parse(text);
  } catch (const toml::parse_error&) {
    return text;
  }
  for (const char* table : {"contacts", "events", "outputs", "invariants", "reference", "visual", "optimize", "controller"})
    root.erase(table);
  if (toml::array* constraints = root["constraints"].as_array()) {
    toml::array kept;
    for (std::size_t k = 0; k < constraints->size(); ++k)
      if (!removed.count(static_cast<int>(k))) kept.push_back(*(*constraints)[k].as_string());
    if (kept.empty()) root.erase("constraints");
    else root.insert_or_assign("constraints", kept);
  }
  root.erase("dependent");  // one per constraint: the suslov model's, not the switched model's
  if (toml::table* initial = root["initial"].as_table()) {
    std::vector<std::string> multipliers;
    for (auto&& [key, value] : *initial)
      if (looks_like_multiplier(std::string(key.str()))) multipliers.emplace_back(key.str());
    for (const std::string& key : multipliers) initial->erase(key);  // guesses; the run's own values follow
  }
  if (!added_forces.empty()) {
    if (!root.contains("forces")) root.insert("forces", toml::table{});
    toml::table& forces = *root["forces"].as_table();
    for (const auto& [coordinate, force] : added_forces) {
      const toml::node* old = forces.get(coordinate);
      const std::string sum = old && old->is_string() ? "(" + *old->value<std::string>() + ") + (" + force + ")" : force;
      forces.insert_or_assign(coordinate, sum);
    }
  }
  std::ostringstream out;
  out << toml::toml_formatter(root);
  return out.str();
}

std::string equations_source(const std::string& text) {
  toml::table root;
  try {
    root = toml::parse(text);
  } catch (const toml::parse_error&) {
    return text;
  }
  root.erase("initial");
  root.erase("simulate");
  root.erase("optimize");  // steers nhc optimize, not part of the equations
  root.erase("visual");  // drawn from the run, not part of the equations
  root.erase("events");  // located along the run, not part of the equations
  root.erase("contacts");  // forces read from the multipliers along the run
  root.erase("controller");  // sets the inputs along the run, not part of the equations
  root.erase("outputs");  // sampled from the run, not part of the equations
  std::ostringstream out;
  out << toml::toml_formatter(root);
  return out.str();
}

std::string scene_text_with_inputs(const std::string& text, const std::map<std::string, std::string>& laws) {
  const toml::table root = toml::parse(text);
  // Each entry's value replaced in place, the last in the text first, so that every other line
  // and column of the file (its messages' locations) stays where it was.
  std::vector<std::pair<std::size_t, std::pair<std::size_t, std::string>>> edits;
  std::vector<std::size_t> line_start{0};
  for (std::size_t i = 0; i < text.size(); ++i)
    if (text[i] == '\n') line_start.push_back(i + 1);
  const auto offset = [&](const toml::source_position& at) {
    return line_start.at(static_cast<std::size_t>(at.line) - 1) + static_cast<std::size_t>(at.column) - 1;
  };
  const toml::table* inputs = root["inputs"].as_table();
  for (const auto& [name, law] : laws) {
    const toml::node* node = inputs ? inputs->get(name) : nullptr;
    if (!node) throw std::invalid_argument("the scene has no input '" + name + "'");
    if (law.find_first_of("\"\\\n") != std::string::npos)
      throw std::invalid_argument("the law of '" + name + "' holds a quote, backslash or line break");
    const std::size_t begin = offset(node->source().begin), end = offset(node->source().end);
    edits.push_back({begin, {end, "\"" + law + "\""}});
  }
  std::sort(edits.begin(), edits.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::string out = text;
  for (const auto& [begin, edit] : edits) out.replace(begin, edit.first - begin, edit.second);
  return out;
}

bool scene_gives_t_end(const std::string& text) {
  return toml::parse(text)["simulate"]["t_end"].node() != nullptr;
}

std::set<std::string> scene_definition_names(const std::string& text) {
  std::set<std::string> names;
  if (const toml::table* definitions = toml::parse(text)["definitions"].as_table())
    for (const auto& [key, value] : *definitions) names.insert(std::string(key.str()));
  return names;
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
