#include "nhc/emit/expression_printer.hpp"

#include <algorithm>
#include <sstream>
#include <vector>

namespace nhc {

namespace {

using GiNaC::ex;

std::string ginac_text(const ex& e) {
  std::ostringstream out;
  out << GiNaC::dflt << e;
  return out.str();
}

// GiNaC orders the terms of sums and products by hash values that involve type-info
// addresses, so its own printer can list them differently from one run to the next. This
// printer produces the same syntax (readable by parse_expression) with terms and factors
// sorted by their printed text, so that equal expressions print identically in every run.
class CanonicalText {
 public:
  /// Precedence of the context: 0 sum, 1 product factor, 2 power base.
  std::string print(const ex& e, int context = 0) const {
    if (GiNaC::is_a<GiNaC::add>(e)) return wrap(sum(e), context > 0);
    if (GiNaC::is_a<GiNaC::mul>(e)) return wrap(product(e), context > 1 || (starts_negative(e) && context > 0));
    if (GiNaC::is_a<GiNaC::power>(e)) return wrap(power(e), context > 1);
    if (GiNaC::is_a<GiNaC::numeric>(e)) {
      const GiNaC::numeric& n = GiNaC::ex_to<GiNaC::numeric>(e);
      const bool needs = (n.is_negative() && context > 0) || (!n.is_integer() && context > 1);
      return wrap(ginac_text(e), needs);
    }
    if (GiNaC::is_a<GiNaC::function>(e) && !GiNaC::is_a<GiNaC::fderivative>(e)) {
      std::string out = GiNaC::ex_to<GiNaC::function>(e).get_name() + "(";
      for (std::size_t i = 0; i < e.nops(); ++i) out += (i ? "," : "") + print(e.op(i));
      return out + ")";
    }
    return ginac_text(e);  // symbols, constants, anything else
  }

 private:
  static std::string wrap(const std::string& s, bool parenthesize) {
    return parenthesize ? "(" + s + ")" : s;
  }
  static bool starts_negative(const ex& e) {
    if (GiNaC::is_a<GiNaC::numeric>(e)) return GiNaC::ex_to<GiNaC::numeric>(e).is_negative();
    if (GiNaC::is_a<GiNaC::mul>(e)) {
      const ex c = e.op(e.nops() - 1);  // GiNaC keeps the numeric coefficient last
      return GiNaC::is_a<GiNaC::numeric>(c) && GiNaC::ex_to<GiNaC::numeric>(c).is_negative();
    }
    return false;
  }

  /// (is_negative, text of the magnitude) of one term of a sum.
  std::pair<bool, std::string> signed_term(const ex& term) const {
    const std::string text = print(term, 0);
    if (!text.empty() && text[0] == '-') return {true, text.substr(1)};
    return {false, text};
  }

  bool first_term_negative(const ex& sum_expression) const {
    std::vector<std::pair<std::string, bool>> terms;
    for (std::size_t i = 0; i < sum_expression.nops(); ++i) {
      auto [negative, text] = signed_term(sum_expression.op(i));
      terms.emplace_back(text, negative);
    }
    return std::min_element(terms.begin(), terms.end())->second;
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
        f = (-f).expand();
        coefficient = -coefficient;
      }
      factors.push_back(print(f, 1));
    }
    std::sort(factors.begin(), factors.end());
    std::string out;
    if (coefficient.is_equal(-1)) out = "-";
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
    std::string out = print(base, 2) + "^";
    if (GiNaC::is_a<GiNaC::numeric>(exponent) && GiNaC::ex_to<GiNaC::numeric>(exponent).is_nonneg_integer())
      return out + ginac_text(exponent);
    return out + "(" + print(exponent) + ")";
  }
};

}  // namespace

std::string to_text(const GiNaC::ex& e) { return CanonicalText().print(e); }

std::string to_latex(const GiNaC::ex& e) {
  std::ostringstream out;
  out << GiNaC::latex << e;
  return out.str();
}

}  // namespace nhc
