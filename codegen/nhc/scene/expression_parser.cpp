#include "nhc/scene/expression_parser.hpp"

#include "nhc/base/primed_name.hpp"

#include "nhc/expr/elementary_derivatives.hpp"
#include "nhc/expr/traversal.hpp"
#include "nhc/expr/work_budget.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <sstream>
#include <vector>

namespace nhc {

namespace {

using GiNaC::ex;

/// A name for a message: long ones cut after 40 characters.
std::string shown(const std::string& name) { return name.size() <= 40 ? name : name.substr(0, 40) + "..."; }

bool is_name_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool is_name_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

/// Splits `x_d12` into ("x", 12); returns nullopt when the name has no `_d<digits>` tail.
std::optional<std::pair<std::string, int>> split_jet_suffix(const std::string& name) {
  const auto pos = name.rfind("_d");
  if (pos == std::string::npos || pos == 0 || pos + 2 >= name.size()) return std::nullopt;
  const std::string digits = name.substr(pos + 2);
  if (digits.size() > 3) return std::pair<std::string, int>(name.substr(0, pos), 1000);
  for (char c : digits)
    if (!std::isdigit(static_cast<unsigned char>(c))) return std::nullopt;
  if (digits[0] == '0') return std::nullopt;
  return std::pair<std::string, int>(name.substr(0, pos), std::stoi(digits));
}

/// Index α (0-based) when `name` is lambda<α+1>.
std::optional<int> multiplier_index(const std::string& name) {
  if (name.rfind("lambda", 0) != 0 || name.size() == 6) return std::nullopt;
  const std::string digits = name.substr(6);
  if (digits[0] == '0' || digits.size() > 6) return std::nullopt;
  for (char c : digits)
    if (!std::isdigit(static_cast<unsigned char>(c))) return std::nullopt;
  return std::stoi(digits) - 1;
}

class Parser {
 public:
  Parser(const std::string& text, const JetSpace& jet, const ExpressionRules& rules)
      : text_(text), jet_(jet), rules_(rules) {
    register_elementary_derivatives();  // the functions this parser makes differentiate fast
  }

  Value parse() {
    if (rules_.input_limits && text_.size() > kMaxExpressionLength)
      fail(0, "expression longer than " + std::to_string(kMaxExpressionLength) + " characters");
    skip_space();
    if (at_end()) fail(pos_, "empty expression");
    Value v = expr();
    skip_space();
    if (!at_end()) fail(pos_, std::string("unexpected '") + text_[pos_] + "'");
    if (rules_.input_limits)
      for (const ex& e : v.entries) check_size(e);
    return v;
  }

 private:
  /// The input limits on a finished expression: its numbers, its size in nodes (definitions
  /// substituted), its products, and how far it would expand.
  void check_size(const ex& e) const {
    std::size_t nodes = 0;
    for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it) {
      if (++nodes > kMaxNodes)
        fail(0, "the expression is larger than " + std::to_string(kMaxNodes) + " nodes (definitions substituted)");
      if (GiNaC::is_exactly_a<GiNaC::mul>(*it) && it->nops() > kMaxFactors)
        fail(0, "a product of more than " + std::to_string(kMaxFactors) + " factors");
    }
    if (work_budget::function_nesting(e, kMaxFunctionNesting + 1) > kMaxFunctionNesting)
      fail(0, "functions nested more than " + std::to_string(kMaxFunctionNesting) + " deep (definitions substituted)");
    if (rules_.node_budget) {
      if (nodes > *rules_.node_budget)
        fail(0, "the scene's expressions are larger than " + std::to_string(kMaxSceneNodes) +
                    " nodes in all (definitions counted at every use)");
      *rules_.node_budget -= nodes;
    }
    if (has_large_number(e, true))
      fail(0, "a number in the expression is too large (beyond double precision or more than " +
                  std::to_string(kMaxPowerBits) + " bits)");
    if (work_budget::expanded_terms(e) > work_budget::kMaxExpandedTerms)
      fail(0, "the expression expands to more than " +
                  std::to_string(static_cast<long>(work_budget::kMaxExpandedTerms)) + " terms");
  }

  [[noreturn]] void fail(std::size_t at, const std::string& message) const { throw ExpressionSyntaxError(at, message); }
  bool at_end() const { return pos_ >= text_.size(); }
  char peek() const { return at_end() ? '\0' : text_[pos_]; }
  void skip_space() {
    while (!at_end() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
  }
  bool accept(char c) {
    skip_space();
    if (peek() != c) return false;
    ++pos_;
    return true;
  }

  struct DepthGuard {
    Parser& p;
    explicit DepthGuard(Parser& parser) : p(parser) {
      if (++p.depth_ > (p.rules_.input_limits ? 1 : 20) * kMaxExpressionDepth)
        p.fail(p.pos_, "expression nested more than " + std::to_string(kMaxExpressionDepth) + " levels deep");
    }
    ~DepthGuard() { --p.depth_; }
  };

  /// True when a rational number of e has a numerator or denominator of more than kMaxPowerBits
  /// bits or is too large for a double: looking at e's own coefficients (cheap, after each operation) or, with `deep`,
  /// at every number in it. Products of numbers grow without a power (1e400*1e400*…), and every number nhc accepts must
  /// print as a literal it reads back.
  static bool has_large_number(const ex& e, bool deep) {
    auto large = [](const ex& x) {
      if (!GiNaC::is_a<GiNaC::numeric>(x)) return false;
      const auto& n = GiNaC::ex_to<GiNaC::numeric>(x);
      if (!n.is_rational()) return false;
      const long numerator_bits = GiNaC::numer(n).int_length();
      const long denominator_bits = GiNaC::denom(n).int_length();
      // |n| < 2^(numerator_bits - denominator_bits + 1): beyond 2^1023 no double holds it, and
      // the generated code and the runtime compute in doubles.
      return std::max(numerator_bits, denominator_bits) > kMaxPowerBits || numerator_bits - denominator_bits > 1022;
    };
    if (deep) return any_subexpression(e, large);
    if (large(e)) return true;
    if (GiNaC::is_exactly_a<GiNaC::mul>(e) || GiNaC::is_exactly_a<GiNaC::add>(e))
      for (std::size_t k = 0; k < e.nops(); ++k)
        if (large(e.op(k)) || (GiNaC::is_exactly_a<GiNaC::mul>(e.op(k)) && large(e.op(k).op(e.op(k).nops() - 1))))
          return true;
    return false;
  }

  /// Height of the tower of powers with non-numeric exponents in e (x^y: 1, x^x^y: 2).
  static int exponent_tower(const ex& e) {
    if (GiNaC::is_exactly_a<GiNaC::power>(e) && !GiNaC::is_a<GiNaC::numeric>(e.op(1)))
      return 1 + std::max(exponent_tower(e.op(0)), exponent_tower(e.op(1)));
    int height = 0;
    for (std::size_t k = 0; k < e.nops(); ++k) height = std::max(height, exponent_tower(e.op(k)));
    return height;
  }

  /// True when e contains a number that is not real (GiNaC evaluates sqrt(-4) to 2*I).
  static bool has_complex_number(const ex& e) {
    return any_subexpression(
        e, [](const ex& x) { return GiNaC::is_a<GiNaC::numeric>(x) && !GiNaC::ex_to<GiNaC::numeric>(x).is_real(); });
  }

  /// GiNaC reports 1/0 and similar by throwing; turn that into a positioned error. A complex
  /// constant (sqrt(-4), log(-1)) is refused too: nothing downstream can read `I` back.
  template <class F>
  ex guarded(std::size_t at, F&& f) {
    try {
      ex result = f();
      if (has_complex_number(result)) fail(at, "the expression has a complex value");
      if (rules_.input_limits && has_large_number(result, false))
        fail(at, "a number in the result is too large (beyond double precision or more than " +
                     std::to_string(kMaxPowerBits) + " bits)");
      return result;
    } catch (const GiNaC::pole_error&) {
      fail(at, "division by zero");
    } catch (const std::overflow_error&) {
      fail(at, "division by zero");
    } catch (const std::domain_error& e) {
      fail(at, std::string("invalid operation: ") + e.what());
    } catch (const WorkLimitExceeded& e) {
      fail(at, std::string("too large to work with: ") + e.what());
    }
  }

  // Sums and products are collected and built once: adding term by term copies the growing sum
  // each time, quadratic in the number of terms (sin(1)*sin(2)*…*sin(10000) took 17 s).
  Value expr() {
    DepthGuard guard(*this);
    std::vector<Value> terms{term()};
    std::vector<std::size_t> at{0};
    for (;;) {
      skip_space();
      const std::size_t op = pos_;
      if (accept('+')) {
        terms.push_back(term());
      } else if (peek() == '-') {
        ++pos_;
        terms.push_back(-term());
      } else {
        break;
      }
      at.push_back(op);
    }
    if (terms.size() == 1) return terms.front();
    if (std::all_of(terms.begin(), terms.end(), [](const Value& v) { return v.is_scalar(); })) {
      GiNaC::exvector scalars;
      scalars.reserve(terms.size());
      for (const Value& v : terms) scalars.push_back(v.entries[0]);
      return Value::scalar(GiNaC::add(scalars));
    }
    Value sum = terms.front();
    for (std::size_t k = 1; k < terms.size(); ++k) sum = valued(at[k], [&] { return add(sum, terms[k]); });
    return sum;
  }

  /// Shape errors of the value algebra, positioned.
  template <class F>
  Value valued(std::size_t at, F&& f) {
    try {
      return f();
    } catch (const ValueError& e) {
      fail(at, e.what());
    }
  }

  Value term() {
    std::vector<Value> factors{unary()};
    std::vector<std::size_t> at{0};
    // The numbers among the factors, multiplied as they come, so that a product of numbers that
    // grows too large is reported at its own operator.
    GiNaC::numeric coefficient = numeric_coefficient(factors.front());
    std::size_t first_operator = std::string::npos;
    for (;;) {
      skip_space();
      const std::size_t op = pos_;
      Value factor;
      if (accept('*')) {
        factor = unary();
      } else if (accept('/')) {
        const Value rhs = unary();
        if (!rhs.is_scalar()) fail(op, "cannot divide by " + rhs.describe());
        if (rhs.entries[0].is_zero()) fail(op, "division by zero");
        factor = Value::scalar(guarded(op, [&] { return GiNaC::pow(rhs.entries[0], -1); }));
      } else {
        break;
      }
      if (first_operator == std::string::npos) first_operator = op;
      coefficient *= numeric_coefficient(factor);
      if (rules_.input_limits && has_large_number(coefficient, false))
        fail(op, "a number in the result is too large (beyond double precision or more than " +
                     std::to_string(kMaxPowerBits) + " bits)");
      factors.push_back(std::move(factor));
      at.push_back(op);
    }
    if (factors.size() == 1) return factors.front();
    if (std::all_of(factors.begin(), factors.end(), [](const Value& v) { return v.is_scalar(); })) {
      GiNaC::exvector scalars;
      scalars.reserve(factors.size());
      for (const Value& v : factors) scalars.push_back(v.entries[0]);
      return Value::scalar(guarded(first_operator, [&] { return ex(GiNaC::mul(scalars)); }));
    }
    Value product = factors.front();
    for (std::size_t k = 1; k < factors.size(); ++k)
      product = valued(at[k], [&] { return multiply(product, factors[k]); });
    return product;
  }

  /// The numeric factor of a scalar: itself when it is a number, a product's coefficient, else 1.
  static GiNaC::numeric numeric_coefficient(const Value& v) {
    if (!v.is_scalar()) return 1;
    const ex& e = v.entries[0];
    if (GiNaC::is_a<GiNaC::numeric>(e)) return GiNaC::ex_to<GiNaC::numeric>(e);
    if (GiNaC::is_exactly_a<GiNaC::mul>(e) && e.nops() > 0 && GiNaC::is_a<GiNaC::numeric>(e.op(e.nops() - 1)))
      return GiNaC::ex_to<GiNaC::numeric>(e.op(e.nops() - 1));
    return 1;
  }

  Value unary() {
    DepthGuard guard(*this);
    skip_space();
    if (accept('-')) return -unary();
    if (accept('+')) return unary();
    return power();
  }

  Value power() {
    const std::size_t start = pos_;
    Value base_value = postfix();
    skip_space();
    const std::size_t at = pos_;
    if (accept('^')) {
      const Value exponent_value = unary();
      if (!base_value.is_scalar()) fail(start, "cannot raise " + base_value.describe() + " to a power");
      if (!exponent_value.is_scalar()) fail(at, "an exponent must be a scalar, not " + exponent_value.describe());
      const ex& base = base_value.entries[0];
      const ex& exponent = exponent_value.entries[0];
      check_exponent(base, exponent, at);
      // 0^y is 0 for y > 0 and undefined otherwise; its derivative holds log(0) (a crash in
      // every model). Only a positive number is a meaningful exponent of 0.
      if (base.is_zero() &&
          !(GiNaC::is_a<GiNaC::numeric>(exponent) && GiNaC::ex_to<GiNaC::numeric>(exponent).is_positive()))
        fail(at, "0 to a power that is not a positive number is undefined (0^y); write 0 or 1");
      // e^y is exp(y): GiNaC keeps exp(1)^y as a power of a number, which neither prints nor
      // differentiates as the exponential it is.
      const bool of_e = base.is_equal(GiNaC::exp(ex(1)));
      ex result = guarded(at, [&] { return of_e ? GiNaC::exp(exponent) : GiNaC::pow(base, exponent); });
      if (rules_.input_limits && !GiNaC::is_a<GiNaC::numeric>(exponent) && exponent_tower(result) > kMaxExponentTower)
        fail(at, "powers with non-numeric exponents nested more than " + std::to_string(kMaxExponentTower) + " deep");
      return Value::scalar(result);
    }
    return base_value;
  }

  /// A component: v[i] (1-based) or M[i, j]; the indices are positive integers.
  Value postfix() {
    Value v = primary();
    skip_space();
    const std::size_t at = pos_;
    if (!accept('[')) return v;
    std::vector<long> indices;
    do {
      skip_space();
      const std::size_t index_at = pos_;
      const Value index = expr();
      if (!index.is_scalar() || !GiNaC::is_a<GiNaC::numeric>(index.entries[0]) ||
          !GiNaC::ex_to<GiNaC::numeric>(index.entries[0]).is_pos_integer() ||
          GiNaC::ex_to<GiNaC::numeric>(index.entries[0]).to_double() > 1e6)
        fail(index_at, "an index must be a positive integer (components count from 1)");
      indices.push_back(GiNaC::ex_to<GiNaC::numeric>(index.entries[0]).to_long());
    } while (accept(','));
    if (!accept(']')) fail(pos_, "expected ']' after the index");
    return valued(at, [&] { return component(v, indices); });
  }

  /// [a, b, c] is a vector; [[a, b], [c, d]] a matrix whose rows are the inner vectors.
  Value bracket_literal(std::size_t start) {
    std::vector<Value> items;
    do {
      items.push_back(expr());
    } while (accept(','));
    if (!accept(']')) fail(pos_, "expected ']' or ',' in the list");
    if (std::all_of(items.begin(), items.end(), [](const Value& v) { return v.is_scalar(); })) {
      if (items.size() < 2) fail(start, "a vector needs at least two components");
      std::vector<ex> entries;
      for (const Value& v : items) entries.push_back(v.entries[0]);
      return Value::vector(std::move(entries));
    }
    const unsigned cols = items.front().rows;
    std::vector<ex> entries;
    for (const Value& row : items) {
      if (!row.is_vector() || row.rows != cols)
        fail(start, "the rows of a matrix must be vectors of one length (got " + items.front().describe() + " and " +
                        row.describe() + ")");
      entries.insert(entries.end(), row.entries.begin(), row.entries.end());
    }
    return Value::matrix(static_cast<unsigned>(items.size()), cols, std::move(entries));
  }

  /// Numeric exponents are bounded: an exact power of a number must stay a reasonable size,
  /// and a power of an expression must stay expandable (GiNaC expands integer powers of sums).
  void check_exponent(const ex& base, const ex& exponent, std::size_t at) {
    if (!GiNaC::is_a<GiNaC::numeric>(exponent)) return;
    const auto& n = GiNaC::ex_to<GiNaC::numeric>(exponent);
    // Checked here rather than left to GiNaC, whose exception for 0^0 leaks the power object.
    if (base.is_zero() && !n.is_positive()) fail(at, "0^" + to_string_of(n) + " is undefined");
    if (!n.is_rational() || !rules_.input_limits) return;
    const double magnitude = std::abs(n.to_double());
    if (GiNaC::is_a<GiNaC::numeric>(base)) {
      const auto& b = GiNaC::ex_to<GiNaC::numeric>(base);
      if (!b.is_rational() || b.is_zero()) return;
      const double bits = std::max(GiNaC::numer(b).int_length(), GiNaC::denom(b).int_length());
      if (bits * magnitude > kMaxPowerBits)
        fail(at, "the number this power gives is too large (more than " + std::to_string(kMaxPowerBits) + " bits)");
    } else if (magnitude > kMaxExponent) {
      fail(at, "exponent too large (the limit is " + std::to_string(kMaxExponent) + ")");
    }
  }

  static std::string to_string_of(const GiNaC::numeric& n) {
    std::ostringstream out;
    out << n;
    return out.str();
  }

  Value primary() {
    DepthGuard guard(*this);
    skip_space();
    const std::size_t start = pos_;
    if (at_end()) fail(pos_, "expected a number, name or '(' but the expression ended");
    const char c = peek();
    if (c == '(') {
      ++pos_;
      Value inner = expr();
      if (!accept(')')) fail(pos_, "expected ')'");
      return inner;
    }
    if (c == '[') {
      ++pos_;
      return bracket_literal(start);
    }
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') return Value::scalar(number());
    if (is_name_start(c)) {
      while (!at_end() && is_name_char(peek())) ++pos_;
      const std::string name = text_.substr(start, pos_ - start);
      std::size_t after_name = pos_;
      skip_space();
      if (peek() == '(') return call(name, start);
      pos_ = after_name;
      int primes = 0;
      while (peek() == '\'') {
        ++primes;
        ++pos_;
      }
      return variable(name, primes, start);
    }
    if (c == '*' && pos_ > 0 && text_[pos_ - 1] == '*')
      fail(pos_ - 1, "unexpected '**': powers are written with ^ (x^2)");
    fail(pos_, std::string("unexpected '") + c + "'");
  }

  /// What the writer of an unknown name probably meant: x' for x_dot, xdot, dx or x_t; x'' for
  /// x_ddot; the multipliers there are; a known name one or two letters away. "" when nothing is
  /// close.
  std::string hint_for(const std::string& name) const {
    const auto is_coordinate = [&](const std::string& n) { return jet_.coordinate_index(n).has_value(); };
    static const std::vector<std::pair<std::string, int>> suffixes = {{"_ddot", 2}, {"ddot", 2}, {"_dd", 2}, {"_tt", 2},
                                                                      {"_dot", 1},  {"dot", 1},  {"_t", 1},  {"d", 1}};
    for (const auto& [suffix, order] : suffixes)
      if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0 &&
          is_coordinate(name.substr(0, name.size() - suffix.size())))
        return "derivatives are written with primes: " +
               base::primed_name(name.substr(0, name.size() - suffix.size()), order);
    if (name.size() > 1 && name[0] == 'd' && is_coordinate(name.substr(1)))
      return "derivatives are written with primes: " + name.substr(1) + "'";
    if (auto alpha = multiplier_index(name); alpha && *alpha >= jet_.multiplier_count())
      return jet_.multiplier_count() == 0
                 ? "the scene has no constraints, so no multipliers"
                 : "the multipliers are lambda1 to lambda" + std::to_string(jet_.multiplier_count());
    std::vector<std::string> known = jet_.coordinates();
    known.insert(known.end(), jet_.parameters().begin(), jet_.parameters().end());
    std::string best;
    std::size_t best_distance = name.size() < 4 ? 1 : 2;
    for (const std::string& k : known)
      if (const std::size_t d = edit_distance(name, k); d <= best_distance && (best.empty() || d < best_distance)) {
        best = k;
        best_distance = d;
      }
    return best.empty() ? "" : "did you mean '" + best + "'?";
  }

  /// Levenshtein distance (names are short).
  static std::size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
      std::size_t diagonal = row[0];
      row[0] = i;
      for (std::size_t j = 1; j <= b.size(); ++j) {
        const std::size_t above = row[j];
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
        diagonal = above;
      }
    }
    return row[b.size()];
  }

  ex number() {
    const std::size_t start = pos_;
    std::string digits;
    int decimals = 0;
    while (std::isdigit(static_cast<unsigned char>(peek()))) digits += text_[pos_++];
    if (peek() == '.') {
      ++pos_;
      while (std::isdigit(static_cast<unsigned char>(peek()))) {
        digits += text_[pos_++];
        ++decimals;
      }
    }
    if (digits.empty()) fail(start, "malformed number");
    long exponent = 0;
    if (peek() == 'e' || peek() == 'E') {
      std::size_t save = pos_;
      ++pos_;
      int sign = 1;
      if (peek() == '+' || peek() == '-') {
        if (peek() == '-') sign = -1;
        ++pos_;
      }
      std::string exp_digits;
      while (std::isdigit(static_cast<unsigned char>(peek()))) exp_digits += text_[pos_++];
      if (exp_digits.empty()) {
        pos_ = save;
        fail(start, "malformed number exponent");
      }
      if (exp_digits.size() > 4 && rules_.input_limits) fail(start, "number exponent out of range");
      if (exp_digits.size() > 9) fail(start, "number exponent out of range");
      exponent = sign * std::stol(exp_digits);
    }
    // A literal may have as many digits as a kMaxPowerBits-bit number (1234): whatever nhc
    // prints, it reads back.
    if (rules_.input_limits && digits.size() > 1240) fail(start, "number has too many digits");
    exponent -= decimals;
    const long range = rules_.input_limits ? 400 : 100000;
    if (exponent > range || exponent < -range) fail(start, "number out of range (|exponent| > 400)");
    GiNaC::numeric value(digits.c_str());
    const GiNaC::numeric scale = GiNaC::pow(GiNaC::numeric(10), GiNaC::numeric(exponent));
    if (is_name_start(peek())) fail(pos_, "a name cannot follow a number directly; write '*'");
    const GiNaC::numeric result = value * scale;
    if (rules_.input_limits && has_large_number(result, false))
      fail(start,
           "number out of range (beyond double precision or more than " + std::to_string(kMaxPowerBits) + " bits)");
    return result;
  }

  Value call(const std::string& name, std::size_t start) {
    static const std::map<std::string, std::function<ex(const ex&)>> unary_functions = {
        {"sin", [](const ex& a) { return GiNaC::sin(a); }},     {"cos", [](const ex& a) { return GiNaC::cos(a); }},
        {"tan", [](const ex& a) { return GiNaC::tan(a); }},     {"exp", [](const ex& a) { return GiNaC::exp(a); }},
        {"log", [](const ex& a) { return GiNaC::log(a); }},     {"sqrt", [](const ex& a) { return GiNaC::sqrt(a); }},
        {"abs", [](const ex& a) { return GiNaC::abs(a); }},     {"sinh", [](const ex& a) { return GiNaC::sinh(a); }},
        {"cosh", [](const ex& a) { return GiNaC::cosh(a); }},   {"tanh", [](const ex& a) { return GiNaC::tanh(a); }},
        {"asin", [](const ex& a) { return GiNaC::asin(a); }},   {"acos", [](const ex& a) { return GiNaC::acos(a); }},
        {"atan", [](const ex& a) { return GiNaC::atan(a); }},   {"asinh", [](const ex& a) { return GiNaC::asinh(a); }},
        {"acosh", [](const ex& a) { return GiNaC::acosh(a); }}, {"atanh", [](const ex& a) { return GiNaC::atanh(a); }},
    };
    const auto& names = function_names();
    if (std::find(names.begin(), names.end(), name) == names.end())
      fail(start, "unknown function '" + shown(name) + "'");
    accept('(');
    std::vector<Value> args;
    std::vector<std::size_t> arg_positions;
    do {
      skip_space();
      arg_positions.push_back(pos_);
      args.push_back(expr());
    } while (accept(','));
    if (!accept(')')) fail(pos_, "expected ')' after the arguments of " + name);
    const bool binary = name == "atan2" || name == "dot" || name == "cross";
    const std::size_t expected = name == "quat" ? 4 : binary ? 2 : 1;
    if (args.size() != expected)
      fail(start, name + " takes " + std::to_string(expected) + " argument" + (expected == 1 ? "" : "s") + ", got " +
                      std::to_string(args.size()));
    if (auto it = unary_functions.find(name); it != unary_functions.end()) {
      const ex& a = scalar_argument(name, args[0], arg_positions[0]);
      return Value::scalar(guarded(start, [&] { return it->second(a); }));
    }
    if (name == "atan2") {
      const ex& y = scalar_argument(name, args[0], arg_positions[0]);
      const ex& x = scalar_argument(name, args[1], arg_positions[1]);
      return Value::scalar(guarded(start, [&] { return GiNaC::atan2(y, x); }));
    }
    // rotx(a) and omega(R) differentiate their arguments: GiNaC may throw there too (the
    // derivative of 0^y holds log(0)).
    try {
      return vector_function(name, args, start, arg_positions);
    } catch (const GiNaC::pole_error&) {
      fail(start, "division by zero in " + name + "'s angular velocity");
    } catch (const std::overflow_error&) {
      fail(start, "division by zero in " + name + "'s angular velocity");
    } catch (const std::domain_error& e) {
      fail(start, "invalid operation in " + name + "'s angular velocity: " + e.what());
    }
  }

  const ex& scalar_argument(const std::string& name, const Value& v, std::size_t at) {
    if (!v.is_scalar()) fail(at, name + " takes a scalar, not " + v.describe());
    return v.entries[0];
  }

  /// dot cross norm transpose rotx roty rotz quat omega omega_body (value.hpp).
  Value vector_function(const std::string& name, const std::vector<Value>& args, std::size_t start,
                        const std::vector<std::size_t>& arg_positions) {
    const std::size_t first_argument = arg_positions[0];
    if (name == "quat") {
      std::vector<ex> q;
      for (std::size_t k = 0; k < 4; ++k) q.push_back(scalar_argument(name, args[k], arg_positions[k]));
      return rotation_of_quaternion(q, jet_);
    }
    if (name == "rotx" || name == "roty" || name == "rotz") {
      const ex& angle = scalar_argument(name, args[0], first_argument);
      const Value r = name == "rotx"   ? rotation_x(angle, jet_)
                      : name == "roty" ? rotation_y(angle, jet_)
                                       : rotation_z(angle, jet_);
      return r;
    }
    return valued(start, [&]() -> Value {
      if (name == "dot") return Value::scalar(dot(args[0], args[1]));
      if (name == "cross") return cross(args[0], args[1]);
      if (name == "norm") return Value::scalar(norm(args[0]));
      if (name == "transpose") return transpose(args[0]);
      if (name == "omega") return spatial_angular_velocity(args[0], jet_, rules_.rotation_check);
      return body_angular_velocity(args[0], jet_, rules_.rotation_check);
    });
  }

  Value variable(const std::string& name, int primes, std::size_t start) {
    // Printed jet form x_d2 is accepted as a spelling of x''.
    std::string base = name;
    int order = primes;
    if (!jet_.parameter_index(name) && !jet_.input_index(name) && !known_variable(name)) {
      if (auto split = split_jet_suffix(name)) {
        if (known_variable(split->first)) {
          if (primes > 0) fail(start, "'" + name + "' cannot take primes as well");
          base = split->first;
          order = split->second;
        }
      }
    }
    if (order > kMaxDerivativeOrder)
      fail(start, "derivative order " + std::to_string(order) + " of '" + shown(base) + "' exceeds the limit of " +
                      std::to_string(kMaxDerivativeOrder));
    // GiNaC prints π as `Pi` (acos(-1), atan(1)*4 evaluate to it); read it back.
    if (base == "Pi" && !jet_.parameter_index(base) && !jet_.input_index(base) && !known_variable(base)) {
      if (order > 0) fail(start, "'Pi' is a constant and cannot carry primes");
      return Value::scalar(GiNaC::Pi);
    }
    if (base == "t") {
      if (!rules_.allow_time) fail(start, "'t' is not allowed here");
      if (order > 0) fail(start, "'t' cannot be differentiated (primes on 't')");
      return Value::scalar(jet_.time());
    }
    if (auto p = jet_.parameter_index(base)) {
      if (order > 0) fail(start, "parameter '" + base + "' cannot carry primes");
      return Value::scalar(jet_.parameter(*p));
    }
    if (auto k = jet_.input_index(base)) {
      if (order > 0) fail(start, "input '" + base + "' cannot carry primes: an input's derivative is not known");
      if (!rules_.allow_coordinates) fail(start, "input '" + base + "' is not allowed here " + allowed_here());
      if (!rules_.allow_inputs)
        fail(start, "input '" + base + "' is not allowed here (an input's law may not use another input)");
      if (rules_.input_law)
        if (std::optional<GiNaC::ex> law = rules_.input_law(*k)) return Value::scalar(*law);
      return Value::scalar(jet_.input(*k));
    }
    if (const std::optional<int> i = jet_.coordinate_index(base)) {
      if (!rules_.allow_coordinates) fail(start, "coordinate '" + base + "' is not allowed here " + allowed_here());
      return Value::scalar(jet_.q(*i, order));
    }
    if (auto alpha = multiplier_index(base); alpha && *alpha < jet_.multiplier_count()) {
      if (!rules_.allow_multipliers) fail(start, "multiplier '" + base + "' is not allowed here");
      return Value::scalar(jet_.lambda(*alpha, order));
    }
    if (rules_.definition)
      if (std::optional<Value> value = rules_.definition(name)) return defined(name, *value, primes, start);
    // The constants π and e, where the scene gives the name no meaning of its own (a parameter,
    // coordinate, input or definition named e keeps its meaning: docs/scenes.md).
    if (name == "pi" || name == "e") {
      if (primes > 0) fail(start, "'" + name + "' is a constant and cannot carry primes");
      return Value::scalar(name == "pi" ? ex(GiNaC::Pi) : GiNaC::exp(ex(1)));
    }
    const std::string hint = base.size() <= 64 ? hint_for(base) : "";
    fail(start, "unknown name '" + shown(base) + "'" + (hint.empty() ? "" : " (" + hint + ")"));
  }

  /// What an expression without coordinates may use, for messages.
  std::string allowed_here() const { return rules_.allow_time ? "(only t and parameters)" : "(only parameters)"; }

  /// A definition's value, differentiated `primes` times with the total derivative D.
  Value defined(const std::string& name, const Value& value, int primes, std::size_t start) {
    if (!rules_.allow_coordinates || !rules_.allow_time)
      for (const ex& e : value.entries) {
        if (!rules_.allow_coordinates && jet_.highest_coordinate_order(e) >= 0)
          fail(start, "definition '" + shown(name) + "' involves coordinates, not allowed here " + allowed_here());
        if (!rules_.allow_time && e.has(jet_.time()))
          fail(start, "definition '" + shown(name) + "' involves 't', not allowed here");
      }
    if (primes == 0) return value;
    Value derivative = total_derivative(value, jet_, primes);
    for (const ex& e : derivative.entries)
      if (jet_.highest_coordinate_order(e) > kMaxDerivativeOrder)
        fail(start, "'" + base::primed_name(shown(name), primes) + "' has derivatives of order above the limit of " +
                        std::to_string(kMaxDerivativeOrder));
    return derivative;
  }

  bool known_variable(const std::string& name) const {
    if (name == "t") return true;
    if (jet_.coordinate_index(name)) return true;
    auto alpha = multiplier_index(name);
    return alpha && *alpha < jet_.multiplier_count();
  }

  const std::string& text_;
  const JetSpace& jet_;
  ExpressionRules rules_;
  std::size_t pos_ = 0;
  int depth_ = 0;
};

}  // namespace

GiNaC::ex parse_expression(const std::string& text, const JetSpace& jet, const ExpressionRules& rules) {
  const Value v = Parser(text, jet, rules).parse();
  if (!v.is_scalar()) throw ExpressionSyntaxError(0, "expected a scalar, but the expression is " + v.describe());
  return v.entries[0];
}

Value parse_value(const std::string& text, const JetSpace& jet, const ExpressionRules& rules) {
  return Parser(text, jet, rules).parse();
}

const std::vector<std::string>& function_names() {
  static const std::vector<std::string> names = {"sin",   "cos",   "tan",   "exp",  "log",   "sqrt",      "abs",
                                                 "sinh",  "cosh",  "tanh",  "asin", "acos",  "atan",      "asinh",
                                                 "acosh", "atanh", "atan2", "dot",  "cross", "norm",      "transpose",
                                                 "rotx",  "roty",  "rotz",  "quat", "omega", "omega_body"};
  return names;
}

}  // namespace nhc
