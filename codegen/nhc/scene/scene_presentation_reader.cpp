// The presentation's tables of a scene file: [outputs], [visual] (docs/architecture.md, "The
// scene's three parts").
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

void SceneReader::read_outputs(const toml::table& root, Scene& scene, const ExpressionRules& rules) {
  if (const toml::node* node = root.get("outputs"))
    scene.outputs = read_quantities(*node, "outputs", "output", *scene.jet, multipliers_allowed(rules));
}

/// A value of the scene language (value.hpp) written at `node`: a string, a number (a scalar)
/// or an array of numbers and strings (a vector).
Value SceneReader::value_at(const toml::node& node, const std::string& what, const JetSpace& jet,
                            const ExpressionRules& rules) {
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
void SceneReader::read_visuals(const toml::table& root, Scene& scene, const ExpressionRules& rules) {
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

void SceneReader::check_visual_value(const toml::node& node, const std::string& what, VisualValueKind kind,
                                     const Value& v, const ExpressionRules& rules) const {
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
std::string SceneReader::color_value(const toml::node& node, const std::string& what) const {
  const std::string c = string_value(node, what);
  const bool hex = c.size() > 1 && c[0] == '#' &&
                   std::all_of(c.begin() + 1, c.end(), [](unsigned char ch) { return std::isxdigit(ch) != 0; });
  if (!hex || (c.size() != 4 && c.size() != 7))
    fail(node, what + " must be \"#rrggbb\" or \"#rgb\" (hexadecimal), not \"" + printable(c) + "\"");
  if (c.size() == 7) return c;
  return std::string{'#', c[1], c[1], c[2], c[2], c[3], c[3]};
}

}  // namespace nhc::scene_reading
