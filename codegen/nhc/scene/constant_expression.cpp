#include "nhc/scene/constant_expression.hpp"

#include <cctype>
#include <cmath>
#include <stdexcept>

namespace nhc {

namespace {

/// Recursive descent: sum := product (('+'|'-') product)*; product := unary (('*'|'/') unary)*;
/// unary := ('+'|'-') unary | power; power := atom ('^' unary)?; atom := number | name | name '(' sum ')' | '(' sum
/// ')'.
class ConstantParser {
 public:
  ConstantParser(const std::string& text, const std::map<std::string, double>& names) : text_(text), names_(names) {}

  double parse() {
    const double v = sum();
    skip_space();
    if (pos_ != text_.size()) error("unexpected '" + std::string(1, text_[pos_]) + "'");
    if (!std::isfinite(v)) throw std::invalid_argument("'" + text_ + "' is not finite");
    return v;
  }

 private:
  [[noreturn]] void error(const std::string& why) const {
    throw std::invalid_argument("'" + text_ + "': " + why + " at column " + std::to_string(pos_ + 1));
  }
  void skip_space() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
  }
  bool accept(char c) {
    skip_space();
    if (pos_ < text_.size() && text_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  double sum() {
    double v = product();
    for (;;) {
      if (accept('+')) v += product();
      else if (accept('-')) v -= product();
      else return v;
    }
  }
  double product() {
    double v = unary();
    for (;;) {
      if (accept('*')) v *= unary();
      else if (accept('/')) {
        const double d = unary();
        if (d == 0.0) error("division by zero");
        v /= d;
      } else return v;
    }
  }
  double unary() {
    if (accept('-')) return -unary();
    if (accept('+')) return unary();
    return power();
  }
  double power() {
    const double base = atom();
    if (accept('^')) return std::pow(base, unary());
    return base;
  }
  double atom() {
    skip_space();
    if (pos_ >= text_.size()) error("expression ends early");
    if (accept('(')) {
      const double v = sum();
      if (!accept(')')) error("')' expected");
      return v;
    }
    const char c = text_[pos_];
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') return number();
    if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') return name();
    error("unexpected '" + std::string(1, c) + "'");
  }
  double number() {
    const char* begin = text_.c_str() + pos_;
    char* end = nullptr;
    const double v = std::strtod(begin, &end);
    if (end == begin) error("a number expected");
    pos_ += static_cast<std::size_t>(end - begin);
    return v;
  }
  double name() {
    const std::size_t start = pos_;
    while (pos_ < text_.size() && (std::isalnum(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '_')) ++pos_;
    const std::string n = text_.substr(start, pos_ - start);
    if (accept('(')) {
      const double x = sum();
      if (!accept(')')) error("')' expected");
      return function(n, x, start);
    }
    if (const auto it = names_.find(n); it != names_.end()) return it->second;
    if (n == "pi") return M_PI;
    if (n == "e") return M_E;
    pos_ = start;
    std::string known = "pi, e";
    for (const auto& [k, v] : names_) known += ", " + k;
    error("unknown name '" + n + "' (known: " + known + ")");
  }
  double function(const std::string& f, double x, std::size_t start) {
    if (f == "sin") return std::sin(x);
    if (f == "cos") return std::cos(x);
    if (f == "tan") return std::tan(x);
    if (f == "asin") return std::asin(x);
    if (f == "acos") return std::acos(x);
    if (f == "atan") return std::atan(x);
    if (f == "sinh") return std::sinh(x);
    if (f == "cosh") return std::cosh(x);
    if (f == "tanh") return std::tanh(x);
    if (f == "asinh") return std::asinh(x);
    if (f == "acosh") return std::acosh(x);
    if (f == "atanh") return std::atanh(x);
    if (f == "exp") return std::exp(x);
    if (f == "log") return std::log(x);
    if (f == "sqrt") return std::sqrt(x);
    if (f == "abs") return std::abs(x);
    pos_ = start;
    error("unknown function '" + f + "'");
  }

  const std::string& text_;
  const std::map<std::string, double>& names_;
  std::size_t pos_ = 0;
};

}  // namespace

double evaluate_constant_expression(const std::string& text, const std::map<std::string, double>& names) {
  return ConstantParser(text, names).parse();
}

}  // namespace nhc
