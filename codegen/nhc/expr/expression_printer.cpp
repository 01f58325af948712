#include "nhc/expr/expression_printer.hpp"

#include <algorithm>
#include <map>
#include <sstream>
#include <unordered_map>

#include "nhc/long_work.hpp"
#include <vector>

namespace nhc {

namespace {

using GiNaC::ex;

std::string ginac_text(const ex& e) {
  std::ostringstream out;
  out << GiNaC::dflt << e;
  return out.str();
}

/// A product whose numeric coefficient (GiNaC keeps it last) is negative, or a negative number:
/// printed with a leading minus sign.
bool starts_negative(const ex& e) {
  if (GiNaC::is_a<GiNaC::numeric>(e)) return GiNaC::ex_to<GiNaC::numeric>(e).is_negative();
  if (GiNaC::is_a<GiNaC::mul>(e)) {
    const ex c = e.op(e.nops() - 1);
    return GiNaC::is_a<GiNaC::numeric>(c) && GiNaC::ex_to<GiNaC::numeric>(c).is_negative();
  }
  return false;
}

/// −s for a sum s, term by term: the same terms with the opposite sign, nothing multiplied out
/// (a printer never expands: work_budget.hpp).
ex negated_sum(const ex& s) {
  GiNaC::exvector terms;
  terms.reserve(s.nops());
  for (std::size_t i = 0; i < s.nops(); ++i) terms.push_back(-s.op(i));
  return GiNaC::add(terms);
}

/// Printed text per subexpression. Printing sorts terms by their text and looks at a sum's
/// first term to choose its sign, so each subexpression's text is asked for more than once;
/// remembering it keeps printing linear in the size of the tree instead of exponential in its
/// depth.
using TextMemo = std::unordered_map<ex, std::string>;  // std::hash<ex>: GiNaC's cached hash

// GiNaC orders the terms of sums and products by hash values that involve type-info
// addresses, so its own printer can list them differently from one run to the next. This
// printer produces the same syntax (readable by parse_expression) with terms and factors
// sorted by their printed text, so that equal expressions print identically in every run.
class CanonicalText {
 public:
  std::string print(const ex& e, Position position = Position::term) const {
    check_for_stop();  // a printed equation may be megabytes long: the work budget may stop it
    const bool brackets = needs_brackets(e, position);
    if (GiNaC::is_a<GiNaC::add>(e) || GiNaC::is_a<GiNaC::mul>(e) || GiNaC::is_a<GiNaC::power>(e))
      return wrap(remembered(e), brackets);
    if (GiNaC::is_a<GiNaC::numeric>(e)) return wrap(ginac_text(e), brackets);
    if (GiNaC::is_a<GiNaC::function>(e) && !GiNaC::is_a<GiNaC::fderivative>(e)) {
      std::string out = GiNaC::ex_to<GiNaC::function>(e).get_name() + "(";
      for (std::size_t i = 0; i < e.nops(); ++i) out += (i ? "," : "") + print(e.op(i));
      return out + ")";
    }
    return ginac_text(e);  // symbols, constants, anything else
  }

 private:
  mutable TextMemo memo_;

  /// The text of a sum, product or power before the context's parentheses, computed once.
  const std::string& remembered(const ex& e) const {
    auto it = memo_.find(e);
    if (it != memo_.end()) return it->second;
    std::string text = GiNaC::is_a<GiNaC::add>(e) ? sum(e) : GiNaC::is_a<GiNaC::mul>(e) ? product(e) : power(e);
    return memo_.emplace(e, std::move(text)).first->second;
  }

  static std::string wrap(const std::string& s, bool parenthesize) { return parenthesize ? "(" + s + ")" : s; }

 public:
  /// True when the first term of the sum, in canonical order, is negative. normal() picks the
  /// sign of a sum factor by GiNaC's term order, which varies between runs; printers flip such
  /// factors so that the first term is positive.
  bool first_term_negative(const ex& sum_expression) const {
    std::vector<std::pair<std::string, bool>> terms;
    for (std::size_t i = 0; i < sum_expression.nops(); ++i) {
      auto [negative, text] = signed_term(sum_expression.op(i));
      terms.emplace_back(text, negative);
    }
    return std::min_element(terms.begin(), terms.end())->second;
  }

 private:
  /// (is_negative, text of the magnitude) of one term of a sum.
  std::pair<bool, std::string> signed_term(const ex& term) const {
    const std::string text = print(term, Position::term);
    if (!text.empty() && text[0] == '-') return {true, text.substr(1)};
    return {false, text};
  }

  std::string sum(const ex& e) const {
    std::vector<std::pair<std::string, bool>> terms;
    for (std::size_t i = 0; i < e.nops(); ++i) {
      auto [negative, text] = signed_term(e.op(i));
      terms.emplace_back(text, negative);
    }
    std::sort(terms.begin(), terms.end());
    std::string out;
    for (std::size_t i = 0; i < terms.size(); ++i) {
      if (terms[i].second) out += "-";
      else if (i > 0) out += "+";
      out += terms[i].first;
    }
    return out;
  }

  std::string product(const ex& e) const {
    GiNaC::numeric coefficient = 1;
    std::vector<std::string> factors;
    for (std::size_t i = 0; i < e.nops(); ++i) {
      ex f = e.op(i);
      if (GiNaC::is_a<GiNaC::numeric>(f)) {
        coefficient *= GiNaC::ex_to<GiNaC::numeric>(f);
        continue;
      }
      // A sum factor (normal() picks its sign by term order, which varies between runs) is
      // printed with its first term positive, the sign moved to the coefficient.
      if (GiNaC::is_a<GiNaC::add>(f) && first_term_negative(f)) {
        f = negated_sum(f);
        coefficient = -coefficient;
      }
      factors.push_back(print(f, Position::factor));
    }
    std::sort(factors.begin(), factors.end());
    std::string out;
    if (coefficient.is_equal(-1)) out = "-";
    else if (!coefficient.is_real()) out = "(" + ginac_text(coefficient) + ")*";
    else if (!coefficient.is_equal(1)) {
      out = ginac_text(coefficient.is_negative() ? ex(-coefficient) : ex(coefficient));
      if (coefficient.is_negative()) out = "-" + out;
      out += "*";
    }
    for (std::size_t i = 0; i < factors.size(); ++i) out += (i ? "*" : "") + factors[i];
    return out;
  }

  std::string power(const ex& e) const {
    const ex base = e.op(0), exponent = e.op(1);
    if (exponent.is_equal(GiNaC::numeric(1, 2))) return "sqrt(" + print(base) + ")";
    std::string out = print(base, Position::base) + "^";
    if (GiNaC::is_a<GiNaC::numeric>(exponent) && GiNaC::ex_to<GiNaC::numeric>(exponent).is_nonneg_integer())
      return out + ginac_text(exponent);
    return out + "(" + print(exponent) + ")";
  }
};

/// LaTeX in the same deterministic order as CanonicalText (terms and factors sorted by their
/// canonical text), with negative powers gathered into one \frac and jet symbols printed by
/// their TeX names (\dot{x}, \lambda_{1}).
class CanonicalLatex {
 public:
  std::string print(const ex& e, Position position = Position::term) const {
    check_for_stop();
    const bool brackets = needs_brackets(e, position);
    if (GiNaC::is_a<GiNaC::add>(e) || GiNaC::is_a<GiNaC::mul>(e) || GiNaC::is_a<GiNaC::power>(e))
      return wrap(remembered(e), brackets);
    if (GiNaC::is_a<GiNaC::numeric>(e)) return wrap(number(GiNaC::ex_to<GiNaC::numeric>(e)), brackets);
    if (GiNaC::is_a<GiNaC::function>(e) && !GiNaC::is_a<GiNaC::fderivative>(e)) return call(e);
    std::ostringstream out;
    out << GiNaC::latex << e;  // symbols (their TeX names) and constants
    return out.str();
  }

 private:
  CanonicalText text_;  // sort keys, the same order as the text form
  mutable TextMemo memo_;

  /// The LaTeX of a sum, product, reciprocal or power before the context's parentheses.
  const std::string& remembered(const ex& e) const {
    auto it = memo_.find(e);
    if (it != memo_.end()) return it->second;
    std::string text = GiNaC::is_a<GiNaC::add>(e)                       ? sum(e)
                       : GiNaC::is_a<GiNaC::mul>(e) || is_reciprocal(e) ? product(e)
                                                                        : power(e);
    return memo_.emplace(e, std::move(text)).first->second;
  }

  static std::string wrap(const std::string& s, bool parenthesize) {
    return parenthesize ? "\\left(" + s + "\\right)" : s;
  }
  static bool is_reciprocal(const ex& e) {
    return GiNaC::is_a<GiNaC::power>(e) && GiNaC::is_a<GiNaC::numeric>(e.op(1)) &&
           GiNaC::ex_to<GiNaC::numeric>(e.op(1)).is_negative();
  }
  static std::string number(const GiNaC::numeric& n) {
    if (!n.is_real()) {  // a + b i, always bracketed
      const GiNaC::numeric im = n.imag();
      std::string out = n.real().is_zero() ? "" : number(n.real()) + (im.is_negative() ? "-" : "+");
      if (im.is_negative() && n.real().is_zero()) out = "-";
      const GiNaC::numeric magnitude = GiNaC::abs(im);
      return "\\left(" + out + (magnitude.is_equal(1) ? "" : number(magnitude) + "\\,") + "\\mathrm{i}\\right)";
    }
    if (n.is_integer()) return ginac_text(n);
    const std::string sign = n.is_negative() ? "-" : "";
    const GiNaC::numeric a = GiNaC::abs(n);
    if (!a.is_rational()) return ginac_text(n);
    return sign + "\\frac{" + ginac_text(a.numer()) + "}{" + ginac_text(a.denom()) + "}";
  }

  std::string sum(const ex& e) const {
    std::vector<std::pair<std::string, ex>> terms;  // sorted by canonical text
    for (std::size_t i = 0; i < e.nops(); ++i) terms.emplace_back(text_.print(e.op(i)), e.op(i));
    std::sort(terms.begin(), terms.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::string out;
    for (std::size_t i = 0; i < terms.size(); ++i) {
      std::string t = print(terms[i].second, Position::term);
      if (i > 0 && t.rfind("-", 0) != 0) out += "+";
      out += t;
    }
    return out;
  }

  /// Numeric coefficient, factors with positive powers over those with negative powers.
  std::string product(const ex& e) const {
    GiNaC::numeric coefficient = 1;
    std::vector<std::pair<std::string, std::string>> upper, lower;  // (sort key, latex)
    auto add_factor = [&](ex f) {
      if (GiNaC::is_a<GiNaC::add>(f) && text_.first_term_negative(f)) {
        f = negated_sum(f);
        coefficient = -coefficient;
      }
      if (GiNaC::is_a<GiNaC::numeric>(f)) {
        coefficient *= GiNaC::ex_to<GiNaC::numeric>(f);
      } else if (is_reciprocal(f)) {
        const ex inverse = GiNaC::pow(f.op(0), -f.op(1));
        lower.emplace_back(text_.print(inverse), print(inverse, Position::factor));
      } else {
        upper.emplace_back(text_.print(f), print(f, Position::factor));
      }
    };
    if (GiNaC::is_a<GiNaC::mul>(e)) {
      for (std::size_t i = 0; i < e.nops(); ++i) add_factor(e.op(i));
    } else {
      add_factor(e);
    }
    std::sort(upper.begin(), upper.end());
    std::sort(lower.begin(), lower.end());
    const bool real = coefficient.is_real();  // a complex coefficient stands whole, bracketed
    const std::string sign = real && coefficient.is_negative() ? "-" : "";
    const GiNaC::numeric a = real ? GiNaC::abs(coefficient) : GiNaC::numeric(1);
    std::string top = a.is_rational() && !a.numer().is_equal(1) ? ginac_text(a.numer()) : "";
    std::string bottom = a.is_rational() && !a.denom().is_equal(1) ? ginac_text(a.denom()) : "";
    if (!a.is_rational()) top = ginac_text(a);
    if (!real) top = number(coefficient);
    top = juxtaposed(top, upper);
    bottom = juxtaposed(bottom, lower);
    if (top.empty()) top = "1";
    if (bottom.empty()) return sign + top;
    return sign + "\\frac{" + top + "}{" + bottom + "}";
  }

  /// Factors side by side after `coefficient`; a thin space beside a name of several letters
  /// (\mathrm{Iby}\,\ddot{\theta}), which would otherwise read as one word with its neighbour.
  static std::string juxtaposed(std::string out, const std::vector<std::pair<std::string, std::string>>& factors) {
    bool previous_long = false;
    for (const auto& f : factors) {
      const bool long_name = f.second.find("\\mathrm{") != std::string::npos;
      if (!out.empty()) out += (long_name || previous_long) ? "\\," : " ";
      out += f.second;
      previous_long = long_name;
    }
    return out;
  }

  std::string power(const ex& e) const {
    const ex base = e.op(0), exponent = e.op(1);
    if (exponent.is_equal(GiNaC::numeric(1, 2))) return "\\sqrt{" + print(base) + "}";
    std::string exponent_text = GiNaC::is_a<GiNaC::numeric>(exponent) ? ginac_text(exponent) : print(exponent);
    // A jet symbol such as \dot{x} takes its exponent directly; other bases are braced.
    return "{" + print(base, Position::base) + "}^{" + exponent_text + "}";
  }

  std::string call(const ex& e) const {
    static const std::map<std::string, std::string> names = {{"sin", "\\sin"},
                                                             {"cos", "\\cos"},
                                                             {"tan", "\\tan"},
                                                             {"exp", "\\exp"},
                                                             {"log", "\\ln"},
                                                             {"sinh", "\\sinh"},
                                                             {"cosh", "\\cosh"},
                                                             {"tanh", "\\tanh"},
                                                             {"asin", "\\arcsin"},
                                                             {"acos", "\\arccos"},
                                                             {"atan", "\\arctan"},
                                                             {"atan2", "\\operatorname{atan2}"},
                                                             {"asinh", "\\operatorname{arsinh}"},
                                                             {"acosh", "\\operatorname{arcosh}"},
                                                             {"atanh", "\\operatorname{artanh}"}};
    const std::string name = GiNaC::ex_to<GiNaC::function>(e).get_name();
    if (name == "abs") return "\\left|" + print(e.op(0)) + "\\right|";
    auto it = names.find(name);
    std::string out = (it != names.end() ? it->second : "\\operatorname{" + name + "}") + "\\left(";
    for (std::size_t i = 0; i < e.nops(); ++i) out += (i ? ", " : "") + print(e.op(i));
    return out + "\\right)";
  }
};

}  // namespace

bool needs_brackets(const GiNaC::ex& e, Position position) {
  if (position == Position::term) return false;
  if (GiNaC::is_a<GiNaC::add>(e)) return true;
  if (GiNaC::is_a<GiNaC::mul>(e) || GiNaC::is_a<GiNaC::power>(e))
    return position == Position::base || starts_negative(e);
  if (GiNaC::is_a<GiNaC::numeric>(e)) {
    const GiNaC::numeric& n = GiNaC::ex_to<GiNaC::numeric>(e);
    return !n.is_real() || n.is_negative() || (position == Position::base && !n.is_integer());
  }
  return false;  // symbols, function calls: self-delimiting
}

std::string to_text(const GiNaC::ex& e) { return CanonicalText().print(e); }

std::string to_latex(const GiNaC::ex& e) { return CanonicalLatex().print(e); }

std::string to_latex(const GiNaC::ex& e, Position position) { return CanonicalLatex().print(e, position); }

}  // namespace nhc
