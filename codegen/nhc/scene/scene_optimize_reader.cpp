// [optimize] of a scene file (docs/scenes.md, "Optimal motions"; docs/optimize.md): the objective,
// the horizon, the boundary conditions and the bounds of `nhc optimize`, as written; the numbers
// take the parameters' values when the problem is solved (optimize::read_settings).
#include "nhc/scene/scene_reader.hpp"

#include <cmath>
#include <set>

#include "nhc/scene/constant_expression.hpp"
#include "nhc/scene/expression_parser.hpp"

namespace nhc {

double SceneNumber::value_at(const std::map<std::string, double>& parameters) const {
  double v = value;
  if (!text.empty()) {
    try {
      v = evaluate_constant_expression(text, parameters);
    } catch (const std::invalid_argument& e) {
      throw InputError(where, what + ": " + e.what());
    }
  }
  if (std::isnan(v) || (!infinite_ok && std::isinf(v))) throw InputError(where, what + " must be a finite number");
  return v;
}

namespace scene_reading {

namespace {

class OptimizeReader {
 public:
  OptimizeReader(Scene& scene, std::string path, const ExpressionRules& rules)
      : scene_(scene), path_(std::move(path)), rules_(rules) {}

  void read(const toml::table& root) {
    const toml::node* node = root.get("optimize");
    if (!node) return;
    const toml::table* table = node->as_table();
    if (!table) fail(*node, "'optimize' must be a table");
    SceneOptimize& s = scene_.optimize;
    s.present = true;
    s.where = at(node->source());
    check_keys(*table, {"objective", "final_cost", "t_end", "intervals", "model", "initial", "final", "bounds"});

    if (const toml::node* n = table->get("objective")) {
      s.objective = expression(*n, "objective");
      s.objective_where = at(n->source());
    }
    if (const toml::node* n = table->get("final_cost")) {
      s.final_cost = expression(*n, "final_cost");
      s.final_cost_where = at(n->source());
    }
    if (const toml::node* n = table->get("t_end")) {
      s.t_end_where = at(n->source());
      if (const toml::array* a = n->as_array()) {
        if (a->size() != 2) fail(*n, "t_end = [low, high] takes two numbers (a free final time within them)");
        s.t_end.push_back(number((*a)[0], "t_end's low bound"));
        s.t_end.push_back(number((*a)[1], "t_end's high bound"));
      } else {
        s.t_end.push_back(number(*n, "t_end"));
      }
    } else {
      s.t_end_where = s.where;
    }
    if (const toml::node* n = table->get("intervals")) {
      const std::optional<int64_t> count = n->value_exact<int64_t>();
      if (!count || *count < 1 || *count > 100000) fail(*n, "intervals must be a whole number from 1 to 100000");
      s.intervals = static_cast<int>(*count);
    }
    if (const toml::node* n = table->get("model")) {
      const std::string name = string(*n, "model");
      const std::optional<ModelKind> kind = parse_model_kind(name);
      if (!kind) fail(*n, "unknown model '" + printable(name) + "' (known: " + model_name_list() + ")");
      s.model = kind;
      s.model_where = at(n->source());
    }
    s.initial = boundary(*table, "initial");
    s.final = boundary(*table, "final");
    if (const toml::node* n = table->get("bounds")) {
      const toml::table* bounds = n->as_table();
      if (!bounds) fail(*n, "[optimize.bounds] must be a table of name = [low, high]");
      for (auto&& [key, value] : *bounds) {
        SceneOptimizeEntry b;
        b.where = at(key.source());
        b.quantity = quantity(std::string(key.str()), b.where, true);
        b.what = b.quantity.name;
        const toml::array* a = value.as_array();
        if (!a || a->size() != 2) fail(value, "a bound is [low, high]");
        b.range = true;
        b.value_where = at(value.source());
        b.low = number((*a)[0], "the low bound of " + b.quantity.name, true);
        b.high = number((*a)[1], "the high bound of " + b.quantity.name, true);
        s.bounds.push_back(b);
      }
    }
  }

 private:
  [[noreturn]] void fail(const toml::node& node, const std::string& message) const {
    throw InputError(at(node.source()), message);
  }
  SourceLocation at(const toml::source_region& r) const {
    return {path_, static_cast<int>(r.begin.line), static_cast<int>(r.begin.column)};
  }

  void check_keys(const toml::table& table, const std::set<std::string>& allowed) const {
    for (auto&& [key, value] : table)
      if (!allowed.count(std::string(key.str()))) {
        std::string list;
        for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
        throw InputError(at(key.source()), "unknown key '" + printable(std::string(key.str())) +
                                               "' in [optimize] (expected one of: " + list + ")");
      }
  }

  std::string string(const toml::node& node, const std::string& what) const {
    const std::optional<std::string> s = node.value_exact<std::string>();
    if (!s) fail(node, what + " must be a string");
    return *s;
  }

  /// A finite number (an integer is one); `infinite_ok` also takes ±inf (an open side of a bound).
  SceneNumber number(const toml::node& node, const std::string& what, bool infinite_ok = false) const {
    SceneNumber number;
    number.what = what;
    number.infinite_ok = infinite_ok;
    number.where = at(node.source());
    if (node.is_integer()) number.value = static_cast<double>(*node.value<int64_t>());
    else if (node.is_floating_point()) number.value = *node.value<double>();
    else if (node.is_string()) {
      // A constant expression of the parameters, as [initial] and [simulate] take ("2*pi", "L/2").
      number.text = *node.value<std::string>();
      number.value = number.value_at(scene_.parameter_values_by_name());
    } else {
      fail(node, what + " must be a finite number");
    }
    if (number.text.empty())
      number.value_at({});  // a finite number as written (an expression's value is checked above)
    return number;
  }

  /// An expression of t, the coordinates, the inputs, the parameters (their values are taken when
  /// the problem is solved) and the [definitions], read by the rules of the Lagrangian.
  GiNaC::ex expression(const toml::node& node, const std::string& what) const {
    const std::string text = string(node, what);
    try {
      return parse_expression(text, *scene_.jet, rules_);
    } catch (const ExpressionSyntaxError& e) {
      SourceLocation where = at(node.source());
      where.column += 1 + static_cast<int>(e.offset());  // past the opening quote
      throw InputError(where, what + ": " + e.what());
    }
  }

  /// "x", "x'", … a coordinate's derivative; an input's name when `inputs_ok`.
  PathQuantity quantity(const std::string& name, const SourceLocation& where, bool inputs_ok) const {
    PathQuantity q;
    q.name = name;
    const std::size_t end = name.find_last_not_of('\'');
    const std::string base = end == std::string::npos ? std::string() : name.substr(0, end + 1);
    q.order = static_cast<int>(name.size() - base.size());
    if (const std::optional<int> i = scene_.jet->coordinate_index(base)) {
      q.index = *i;
      return q;
    }
    if (const std::optional<int> k = scene_.jet->input_index(base); k && inputs_ok && q.order == 0) {
      q.kind = PathQuantity::Kind::input;
      q.index = *k;
      return q;
    }
    for (std::size_t k = 0; k < scene_.outputs.size() && inputs_ok && q.order == 0; ++k)
      if (scene_.outputs[k].name == name) {
        q.kind = PathQuantity::Kind::output;
        q.index = static_cast<int>(k);
        return q;
      }
    std::string names;
    for (int i = 0; i < scene_.coordinate_count(); ++i)
      names += (names.empty() ? "" : ", ") + scene_.jet->coordinates()[static_cast<std::size_t>(i)];
    if (inputs_ok) {
      for (const std::string& u : scene_.jet->inputs()) names += ", " + u;
      for (const SceneQuantity& o : scene_.outputs) names += ", " + o.name;
    }
    throw InputError(where,
                     "unknown name '" + printable(name) + "' (coordinates with primes for derivatives: " + names + ")");
  }

  std::vector<SceneOptimizeEntry> boundary(const toml::table& table, const std::string& key) const {
    std::vector<SceneOptimizeEntry> out;
    const toml::node* node = table.get(key);
    if (!node) return out;
    const toml::table* values = node->as_table();
    if (!values) fail(*node, "[optimize." + key + "] must be a table of name = value");
    for (auto&& [name, value] : *values) {
      SceneOptimizeEntry b;
      b.where = at(name.source());
      b.quantity = quantity(std::string(name.str()), b.where, true);
      if (b.quantity.kind == PathQuantity::Kind::output)
        throw InputError(b.where, "'" + b.quantity.name + "' is a named quantity: [optimize." + key +
                                      "] takes coordinates, their derivatives and inputs");
      const std::string what = std::string(name.str()) + " in [optimize." + key + "]";
      b.what = what;
      b.value_where = at(value.source());
      if (const toml::array* a = value.as_array()) {
        if (a->size() != 2) fail(value, what + ": a bound is [low, high]");
        b.range = true;
        b.low = number((*a)[0], "the low bound of " + what, true);
        b.high = number((*a)[1], "the high bound of " + what, true);
      } else {
        b.low = b.high = number(value, what);
      }
      out.push_back(b);
    }
    return out;
  }

  Scene& scene_;
  std::string path_;
  const ExpressionRules& rules_;
};

}  // namespace

void read_optimize(const toml::table& root, Scene& scene, const std::string& path, const ExpressionRules& rules) {
  OptimizeReader(scene, path, rules).read(root);
}

}  // namespace scene_reading

}  // namespace nhc
