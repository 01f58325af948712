// The Scene's own functions (scene.hpp): parameter values, inputs at a time, names.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>

#include "nhc/scene/constant_expression.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc {

bool is_cpp_keyword(const std::string& name) {
  static const std::set<std::string> keywords = {
      "alignas",     "alignof",   "and",        "and_eq",    "asm",      "auto",         "bitand",
      "bitor",       "bool",      "break",      "case",      "catch",    "char",         "char8_t",
      "char16_t",    "char32_t",  "class",      "compl",     "concept",  "const",        "consteval",
      "constexpr",   "constinit", "const_cast", "continue",  "co_await", "co_return",    "co_yield",
      "decltype",    "default",   "delete",     "do",        "double",   "dynamic_cast", "else",
      "enum",        "explicit",  "export",     "extern",    "false",    "float",        "for",
      "friend",      "goto",      "if",         "inline",    "int",      "long",         "mutable",
      "namespace",   "new",       "noexcept",   "not",       "not_eq",   "nullptr",      "operator",
      "or",          "or_eq",     "private",    "protected", "public",   "register",     "reinterpret_cast",
      "requires",    "return",    "short",      "signed",    "sizeof",   "static",       "static_assert",
      "static_cast", "struct",    "switch",     "template",  "this",     "thread_local", "throw",
      "true",        "try",       "typedef",    "typeid",    "typename", "union",        "unsigned",
      "using",       "virtual",   "void",       "volatile",  "wchar_t",  "while",        "xor",
      "xor_eq"};
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
      const auto same =
          std::find_if(entries.begin(), entries.end(), [&](const auto& e) { return e.first == entry.first; });
      if (same != entries.end()) same->second = entry.second;
      else entries.push_back(entry);
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

}  // namespace nhc
