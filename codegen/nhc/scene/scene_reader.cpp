// What the parts of the scene reader share: locations, refusals, the checked values of a TOML
// node, names, expressions (scene_reader.hpp).
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

bool is_function_name(const std::string& name) {
  const auto& names = function_names();
  return std::find(names.begin(), names.end(), name) != names.end();
}

bool looks_like_multiplier(const std::string& name) {
  if (name.rfind("lambda", 0) != 0 || name.size() == 6) return false;
  return std::all_of(name.begin() + 6, name.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
}

bool has_jet_suffix(const std::string& name) {
  const auto pos = name.rfind("_d");
  if (pos == std::string::npos || pos == 0 || pos + 2 >= name.size()) return false;
  return std::all_of(name.begin() + static_cast<long>(pos) + 2, name.end(),
                     [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
}

SourceLocation SceneReader::at(const toml::source_region& region) const {
  return {path_, static_cast<int>(region.begin.line), static_cast<int>(region.begin.column)};
}

void SceneReader::fail(const toml::node& node, const std::string& message) const {
  throw InputError(at(node), message);
}

/// A number as written (0, 1.5, 1e-08), not std::to_string's 0.000000.
std::string SceneReader::shortest(double v) {
  const std::string shorter = base::number_text(v, 6);  // enough unless that loses the value
  return std::stod(shorter) == v ? shorter : base::number_text(v, 17);
}

void SceneReader::check_keys(const toml::table& table, const std::set<std::string>& allowed) const {
  for (auto&& [key, value] : table) {
    const std::string k(key.str());
    if (!allowed.count(k)) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      throw InputError(at(key.source()), "unknown key '" + printable(k) + "' (expected one of: " + list + ")");
    }
  }
}

const toml::node& SceneReader::require(const toml::table& table, const std::string& key,
                                       const std::string& where) const {
  const toml::node* n = table.get(key);
  if (!n) {
    SourceLocation loc = at(table);
    if (loc.line <= 0) loc = {path_, 1, 1};
    throw InputError(loc, "missing required key '" + key + "' (" + where + ")");
  }
  return *n;
}

std::string SceneReader::string_value(const toml::node& node, const std::string& what) const {
  if (!node.is_string()) fail(node, what + " must be a string, not " + type_name(node));
  return *node.value<std::string>();
}

const toml::array& SceneReader::array_value(const toml::node& node, const std::string& what) const {
  if (!node.is_array()) fail(node, "'" + what + "' must be an array, not " + type_name(node));
  return *node.as_array();
}

const toml::table& SceneReader::table_value(const toml::node& node, const std::string& what) const {
  if (!node.is_table()) fail(node, "'" + what + "' must be a table, not " + type_name(node));
  return *node.as_table();
}

double SceneReader::number_value(const toml::node& node, const std::string& what) const {
  double v = 0;
  if (node.is_integer()) v = static_cast<double>(*node.value<int64_t>());
  else if (node.is_floating_point()) v = *node.value<double>();
  else if (node.is_string()) v = constant_value(node, what);  // "pi/8", "v*cos(pi/6)"
  else fail(node, what + " must be a number, not " + type_name(node));
  if (!std::isfinite(v)) fail(node, what + " must be finite");
  return v;
}

/// The text and place of a number of the experiment, for its re-evaluation from the parameters
/// (NumberExpression; the text "" for a number as such).
NumberExpression SceneReader::number_expression(const toml::node& node) const {
  return {node.is_string() ? *node.value<std::string>() : std::string(), at(node)};
}

std::string SceneReader::type_name(const toml::node& node) {
  switch (node.type()) {
    case toml::node_type::table:
      return "a table";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a floating-point number";
    case toml::node_type::boolean:
      return "a boolean";
    default:
      return "a date or time";
  }
}

void SceneReader::check_variable_name(const toml::node& node, const std::string& n, const std::string& what) {
  check_variable_name_at(at(node), n, what);
}

void SceneReader::check_variable_name_at(const SourceLocation& where, const std::string& n, const std::string& what) {
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
SourceLocation SceneReader::expression_location(const toml::node& node, std::size_t offset) const {
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

GiNaC::ex SceneReader::expression(const toml::node& node, const std::string& what, const JetSpace& jet,
                                  const ExpressionRules& rules) const {
  const std::string text = string_value(node, what);
  try {
    return parse_expression(text, jet, rules);
  } catch (const ExpressionSyntaxError& e) {
    throw InputError(expression_location(node, e.offset()), "in " + what + " \"" + printable(text) + "\": " + e.what());
  }
}

/// work_budget::is_zero(e) for the expression of `node`, a refusal located there.
bool SceneReader::is_zero_at(const toml::node& node, const GiNaC::ex& e) const {
  try {
    return work_budget::is_zero(e);
  } catch (const WorkLimitExceeded& error) {
    throw error.located(at(node), "checking this expression");
  }
}

/// [outputs]: name = "expression" of t, parameters, coordinates, their derivatives and the
/// multipliers; written as CSV columns by nhc simulate, never checked for drift.
ExpressionRules SceneReader::multipliers_allowed(ExpressionRules rules) {
  rules.allow_multipliers = true;
  return rules;
}

/// The entries of a table in the order the file writes them (toml++ keeps tables sorted by key).
std::vector<std::pair<const toml::key*, const toml::node*>> SceneReader::entries_in_file_order(
    const toml::node& node, const std::string& table) const {
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
std::vector<SceneQuantity> SceneReader::read_quantities(const toml::node& node, const std::string& table,
                                                        const std::string& what, const JetSpace& jet,
                                                        const ExpressionRules& rules) {
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

/// A constant expression (constant_expression.hpp) over pi, e and the parameters read so far.
double SceneReader::constant_value(const toml::node& node, const std::string& what) const {
  try {
    return evaluate_constant_expression(*node.value<std::string>(), constants_);
  } catch (const std::invalid_argument& e) {
    fail(node, what + ": " + e.what());
  }
}

}  // namespace nhc::scene_reading
