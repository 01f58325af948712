#include "nhc/linearize/operating_point.hpp"

#include <cctype>
#include <cmath>
#include <cstdlib>

#include "nhc/errors.hpp"
#include "nhc/scene/expression_parser.hpp"

namespace nhc {

namespace {

[[noreturn]] void bad(const std::string& flag, const std::string& message) { throw InputError({flag, 0, 0}, message); }

bool is_variable_of(const Scene& scene, const std::string& name) {
  const JetSpace& jet = *scene.jet;
  for (const std::string& c : jet.coordinates())
    if (c == name) return true;
  for (int a = 0; a < jet.multiplier_count(); ++a)
    if (jet.multiplier_name(a) == name) return true;
  return false;
}

/// "x''" → ("x", 2); "x_d2" → ("x", 2); "x" → ("x", 0).
std::pair<std::string, int> split_derivative(const std::string& name) {
  std::size_t primes = 0;
  while (primes < name.size() && name[name.size() - 1 - primes] == '\'') ++primes;
  if (primes > 0) return {name.substr(0, name.size() - primes), static_cast<int>(primes)};
  const std::size_t d = name.rfind("_d");
  if (d != std::string::npos && d + 2 < name.size() && name.size() - d - 2 <= 2) {
    bool digits = true;
    for (std::size_t k = d + 2; k < name.size(); ++k)
      digits = digits && std::isdigit(static_cast<unsigned char>(name[k]));
    if (digits) return {name.substr(0, d), std::atoi(name.c_str() + d + 2)};
  }
  return {name, 0};
}

}  // namespace

PointOverride parse_point_override(const std::string& text, const std::string& flag) {
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0) bad(flag, flag + " " + text + ": expected NAME=VALUE (e.g. th=0, ph'=5)");
  const std::string value_text = text.substr(eq + 1);
  char* end = nullptr;
  const double value = std::strtod(value_text.c_str(), &end);
  if (value_text.empty() || end != value_text.c_str() + value_text.size() || !std::isfinite(value))
    bad(flag, flag + " " + text + ": the value '" + value_text + "' is not a finite number");
  return {text.substr(0, eq), value};
}

OverrideTarget resolve_override(const Scene& scene, const std::string& name, const std::string& flag) {
  OverrideTarget target;
  if (const auto p = scene.jet->parameter_index(name)) {
    target.parameter = true;
    target.parameter_index = *p;
    return target;
  }
  const auto [variable, order] = split_derivative(name);
  if (!is_variable_of(scene, variable))
    bad(flag, "unknown name '" + name + "' in " + flag + ": not a parameter, coordinate or multiplier of scene " +
                  scene.name + " (derivatives are written with primes: th, ph', x'')");
  if (order > kMaxDerivativeOrder)
    bad(flag, flag + " " + name + ": derivative order " + std::to_string(order) + " is above the limit " +
                  std::to_string(kMaxDerivativeOrder));
  target.variable = variable;
  target.order = order;
  return target;
}

void apply_override(Scene& scene, const OverrideTarget& target, double value) {
  if (target.parameter) {
    scene.parameter_values.at(static_cast<std::size_t>(target.parameter_index)) = value;
    reevaluate_initial_expressions(scene);  // [initial] values written through parameters follow
    return;
  }
  std::vector<double>& values = scene.initial.values[target.variable];
  if (static_cast<int>(values.size()) <= target.order) values.resize(static_cast<std::size_t>(target.order) + 1, 0.0);
  values[static_cast<std::size_t>(target.order)] = value;
  const auto text = scene.initial.expressions.find(target.variable);  // given now: no longer an expression
  if (text != scene.initial.expressions.end() && static_cast<int>(text->second.size()) > target.order)
    text->second[static_cast<std::size_t>(target.order)].clear();
}

}  // namespace nhc
