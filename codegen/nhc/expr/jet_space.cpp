#include "nhc/expr/jet_space.hpp"

#include "nhc/expr/intermediate.hpp"
#include "nhc/expr/stable_symbol.hpp"
#include "nhc/expr/work_budget.hpp"

#include <algorithm>
#include <set>
#include <stdexcept>

namespace nhc {

namespace {

const std::set<std::string>& greek_letters() {
  static const std::set<std::string> names = {
      "alpha", "beta",  "gamma", "delta",  "epsilon", "zeta", "eta",     "theta",   "iota", "kappa", "mu",
      "nu",    "xi",    "pi",    "rho",    "sigma",   "tau",  "upsilon", "phi",     "chi",  "psi",   "omega",
      "Gamma", "Delta", "Theta", "Lambda", "Xi",      "Pi",   "Sigma",   "Upsilon", "Phi",  "Psi",   "Omega"};
  return names;
}

/// LaTeX for a bare name: single letters as they are, Greek names as macros, a letter or a Greek
/// name followed by digits with the digits as subscript (q1 → q_{1}, theta2 → \theta_{2}), others
/// upright.
std::string latex_base(const std::string& name) {
  if (name.size() == 1) return name;
  if (greek_letters().count(name)) return "\\" + name;
  const std::size_t digits = name.find_first_of("0123456789");
  if (digits != std::string::npos && digits > 0 && name.find_first_not_of("0123456789", digits) == std::string::npos) {
    const std::string letters = name.substr(0, digits);
    if (letters.size() == 1 || greek_letters().count(letters))
      return latex_base(letters) + "_{" + name.substr(digits) + "}";
  }
  std::string escaped;
  for (char ch : name) {
    if (ch == '_') escaped += "\\_";
    else escaped += ch;
  }
  return "\\mathrm{" + escaped + "}";
}

}  // namespace

std::string jet_symbol_name(const std::string& variable, int order) {
  if (order == 0) return variable;
  return variable + "_d" + std::to_string(order);
}

std::string jet_symbol_latex(const std::string& variable, VariableKind kind, int order) {
  std::string base;
  if (kind == VariableKind::multiplier) {
    // "lambda7" → \lambda_7 ; \dot\lambda_7 puts the dot on λ, not on the subscript.
    base = "\\lambda_{" + variable.substr(6) + "}";
    switch (order) {
      case 0:
        return base;
      case 1:
        return "\\dot\\lambda_{" + variable.substr(6) + "}";
      case 2:
        return "\\ddot\\lambda_{" + variable.substr(6) + "}";
      case 3:
        return "\\dddot\\lambda_{" + variable.substr(6) + "}";
      default:
        return "\\lambda_{" + variable.substr(6) + "}^{(" + std::to_string(order) + ")}";
    }
  }
  base = latex_base(variable);
  // The dot goes over the letter, not its subscript: \dot{q}_{1}.
  const std::size_t subscript = base.rfind("_{");
  const bool indexed = subscript != std::string::npos && base.find("\\mathrm") == std::string::npos;
  const std::string letter = indexed ? base.substr(0, subscript) : base;
  const std::string index = indexed ? base.substr(subscript) : "";
  switch (order) {
    case 0:
      return base;
    case 1:
      return "\\dot{" + letter + "}" + index;
    case 2:
      return "\\ddot{" + letter + "}" + index;
    case 3:
      return "\\dddot{" + letter + "}" + index;
    default:
      return letter + index + "^{(" + std::to_string(order) + ")}";
  }
}

JetSpace::JetSpace(std::vector<std::string> coordinates, int multiplier_count, std::vector<std::string> parameters,
                   std::vector<std::string> inputs)
    : coordinates_(std::move(coordinates)),
      multiplier_count_(multiplier_count),
      parameter_names_(std::move(parameters)),
      time_(stable_symbol("t")),
      input_names_(std::move(inputs)) {
  for (const auto& name : parameter_names_) parameters_.push_back(stable_symbol(name, latex_base(name)));
  for (const auto& name : input_names_) inputs_.push_back(stable_symbol(name, latex_base(name)));
  input_locations_.assign(input_names_.size(), SourceLocation{"scene", 0, 0});
  // The first of equal names wins, as a search from the front would find it.
  for (std::size_t k = 0; k < coordinates_.size(); ++k)
    coordinate_indices_.emplace(coordinates_[k], static_cast<int>(k));
  for (std::size_t k = 0; k < parameter_names_.size(); ++k)
    parameter_indices_.emplace(parameter_names_[k], static_cast<int>(k));
  for (std::size_t k = 0; k < input_names_.size(); ++k) input_indices_.emplace(input_names_[k], static_cast<int>(k));
}

namespace {

std::optional<int> index_in(const std::unordered_map<std::string, int>& indices, const std::string& name) {
  const auto it = indices.find(name);
  if (it == indices.end()) return std::nullopt;
  return it->second;
}

}  // namespace

std::optional<int> JetSpace::coordinate_index(const std::string& name) const {
  return index_in(coordinate_indices_, name);
}

std::optional<int> JetSpace::input_index(const std::string& name) const { return index_in(input_indices_, name); }

std::optional<int> JetSpace::input_of(const GiNaC::ex& symbol) const {
  for (std::size_t k = 0; k < inputs_.size(); ++k)
    if (symbol.is_equal(inputs_[k])) return static_cast<int>(k);
  return std::nullopt;
}

void JetSpace::set_input_location(int k, SourceLocation where) {
  input_locations_.at(static_cast<size_t>(k)) = std::move(where);
}

std::string JetSpace::multiplier_name(int alpha) const { return "lambda" + std::to_string(alpha + 1); }

std::string JetSpace::variable_name(VariableKind kind, int index) const {
  return kind == VariableKind::coordinate ? coordinates_.at(static_cast<size_t>(index)) : multiplier_name(index);
}

std::optional<int> JetSpace::parameter_index(const std::string& name) const {
  return index_in(parameter_indices_, name);
}

const GiNaC::realsymbol& JetSpace::symbol(const JetCoordinate& c) const {
  auto it = jet_.find(c);
  if (it != jet_.end()) return GiNaC::ex_to<GiNaC::realsymbol>(it->second);
  const int count = c.kind == VariableKind::coordinate ? coordinate_count() : multiplier_count_;
  if (c.index < 0 || c.index >= count || c.order < 0) throw std::out_of_range("jet coordinate out of range");
  const std::string variable = variable_name(c.kind, c.index);
  // Held as an ex: the symbol lives once, on the heap, as long as the space, and every ex made of
  // it (q(), lambda(), ex(symbol(c))) shares that object instead of owning a copy.
  const GiNaC::ex s = stable_symbol(jet_symbol_name(variable, c.order), jet_symbol_latex(variable, c.kind, c.order));
  jet_.emplace(c, s);
  by_symbol_.emplace(s, c);
  creation_order_.push_back(c);
  return GiNaC::ex_to<GiNaC::realsymbol>(jet_.at(c));
}

std::optional<JetCoordinate> JetSpace::classify(const GiNaC::ex& s) const {
  auto it = by_symbol_.find(s);
  if (it == by_symbol_.end()) return std::nullopt;
  return it->second;
}

std::vector<JetCoordinate> JetSpace::jet_coordinates_in(const GiNaC::ex& e) const {
  // Through named intermediates (intermediate.hpp), each shared subexpression visited once.
  std::set<JetCoordinate> found;
  for (const GiNaC::ex& s : symbols_through(e))
    if (auto c = classify(s)) found.insert(*c);
  return {found.begin(), found.end()};
}

GiNaC::ex JetSpace::total_derivative(const GiNaC::ex& e) const {
  // D on the plain symbols: ∂_t, q^(k) → q^(k+1), λ^(k) → λ^(k+1), parameters constant; through
  // intermediates by TotalDerivative (each intermediate's D computed once).
  const TotalDerivative D([this](const GiNaC::ex& s) -> GiNaC::ex {
    if (s.is_equal(time_)) return 1;
    if (const auto c = classify(s)) return symbol({c->kind, c->index, c->order + 1});
    if (const auto k = input_of(s))
      throw InputError(input_locations_[static_cast<size_t>(*k)],
                       "input '" + input_names_[static_cast<size_t>(*k)] +
                           "' would have to be differentiated in time, and an input's derivative is not known: "
                           "the model differentiates an expression that uses it (the Lagrangian, or a constraint "
                           "the index reduction differentiates); inputs may enter [forces] and the constraints "
                           "the model leaves undifferentiated (docs/models.md, \"Inputs\")");
    return 0;
  });
  return D(e);
}

GiNaC::ex JetSpace::total_derivative(const GiNaC::ex& e, int k) const {
  GiNaC::ex result = e;
  for (int j = 0; j < k; ++j) result = work_budget::expand(total_derivative(result));
  return result;
}

int JetSpace::highest_order(const GiNaC::ex& e, VariableKind kind, int index) const {
  int order = -1;
  for (const auto& c : jet_coordinates_in(e))
    if (c.kind == kind && c.index == index) order = std::max(order, c.order);
  return order;
}

int JetSpace::highest_coordinate_order(const GiNaC::ex& e) const {
  int order = -1;
  for (const auto& c : jet_coordinates_in(e))
    if (c.kind == VariableKind::coordinate) order = std::max(order, c.order);
  return order;
}

std::vector<std::pair<JetCoordinate, GiNaC::realsymbol>> JetSpace::symbols() const {
  std::vector<std::pair<JetCoordinate, GiNaC::realsymbol>> out;
  for (const auto& c : creation_order_) out.emplace_back(c, GiNaC::ex_to<GiNaC::realsymbol>(jet_.at(c)));
  return out;
}

}  // namespace nhc
