// Expression parser: precedence, exact numbers, primes and the printed jet spelling, functions,
// and errors with their character offsets. Results are compared symbolically with expressions
// built directly in GiNaC, never as strings.
#include <catch2/catch.hpp>
#include <ginac/ginac.h>

#include <cmath>
#include <string>

#include "nhc/expr/jet_space.hpp"
#include "nhc/scene/expression_parser.hpp"

using GiNaC::ex;
using nhc::ExpressionRules;
using nhc::ExpressionSyntaxError;
using nhc::JetSpace;
using nhc::parse_expression;

namespace {

JetSpace make_jet() { return JetSpace({"x", "y", "theta"}, 2, {"m", "g", "k_1"}); }

bool same(const ex& a, const ex& b) { return (a - b).expand().normal().is_zero(); }

/// Offset of the ExpressionSyntaxError thrown by parsing `text`, or -1 when it parses.
long error_offset(const std::string& text, const JetSpace& jet, const ExpressionRules& rules = {}) {
  try {
    parse_expression(text, jet, rules);
  } catch (const ExpressionSyntaxError& e) {
    return static_cast<long>(e.offset());
  }
  return -1;
}

std::string error_message(const std::string& text, const JetSpace& jet, const ExpressionRules& rules = {}) {
  try {
    parse_expression(text, jet, rules);
  } catch (const ExpressionSyntaxError& e) {
    return e.what();
  }
  return "";
}

ExpressionRules with_multipliers() {
  ExpressionRules r;
  r.allow_multipliers = true;
  return r;
}

}  // namespace

TEST_CASE("precedence and associativity", "[scene][parser]") {
  const JetSpace jet = make_jet();
  const ex m = jet.parameter(0), g = jet.parameter(1), x = jet.q(0, 0);
  CHECK(same(parse_expression("1 + 2*3", jet), 7));
  CHECK(same(parse_expression("(1 + 2)*3", jet), 9));
  CHECK(same(parse_expression("2^3^2", jet), 512));  // right-associative
  CHECK(same(parse_expression("-2^2", jet), -4));    // ^ binds tighter than unary minus
  CHECK(same(parse_expression("2^-1", jet), GiNaC::numeric(1, 2)));
  CHECK(same(parse_expression("2^-1^2", jet), GiNaC::numeric(1, 2)));  // 2^(-(1^2))
  CHECK(same(parse_expression("8/2/2", jet), 2));                      // left-associative
  CHECK(same(parse_expression("8-2-2", jet), 4));
  CHECK(same(parse_expression("m/2*x^2", jet), m * x * x / 2));
  CHECK(same(parse_expression("- - m", jet), m));
  CHECK(same(parse_expression("+m*-g", jet), -m * g));
  CHECK(same(parse_expression("m*g^2/m", jet), g * g));
  CHECK(same(parse_expression("  m\t*\n g ", jet), m * g));
  CHECK(same(parse_expression("2*(m+(g-(x)))", jet), 2 * (m + g - x)));
}

TEST_CASE("numbers are exact", "[scene][parser]") {
  const JetSpace jet = make_jet();
  using GiNaC::numeric;
  const ex v01 = parse_expression("0.1", jet);
  REQUIRE(GiNaC::is_a<numeric>(v01));
  CHECK(GiNaC::ex_to<numeric>(v01) == numeric(1, 10));
  CHECK(GiNaC::ex_to<numeric>(v01).is_rational());
  CHECK(same(parse_expression("1e-3", jet), numeric(1, 1000)));
  CHECK(same(parse_expression("1.5E2", jet), 150));
  CHECK(same(parse_expression("2.5e+1", jet), 25));
  CHECK(same(parse_expression(".5", jet), numeric(1, 2)));
  CHECK(same(parse_expression("5.", jet), 5));
  CHECK(same(parse_expression("0.1 + 0.2 - 0.3", jet), 0));  // exact, not floating point
  CHECK(same(parse_expression("123456789012345678901234567890", jet), numeric("123456789012345678901234567890")));
  CHECK(same(parse_expression("9.81", jet), numeric(981, 100)));
}

TEST_CASE("primes and the printed jet spelling", "[scene][parser]") {
  const JetSpace jet = make_jet();
  CHECK(same(parse_expression("x", jet), jet.q(0, 0)));
  CHECK(same(parse_expression("x'", jet), jet.q(0, 1)));
  CHECK(same(parse_expression("x''", jet), jet.q(0, 2)));
  CHECK(same(parse_expression("theta'''", jet), jet.q(2, 3)));
  CHECK(same(parse_expression("x_d2", jet), jet.q(0, 2)));
  CHECK(same(parse_expression("x_d2 - x''", jet), 0));
  CHECK(same(parse_expression("theta_d4", jet), jet.q(2, 4)));
  CHECK(same(parse_expression("x''^2", jet), GiNaC::pow(jet.q(0, 2), 2)));
  CHECK(same(parse_expression("y'*y''", jet), jet.q(1, 1) * jet.q(1, 2)));
  CHECK(same(parse_expression("x''''''''", jet), jet.q(0, 8)));  // the limit itself
  // Multipliers, with primes or in jet form, only where allowed.
  const ExpressionRules mult = with_multipliers();
  CHECK(same(parse_expression("lambda1", jet, mult), jet.lambda(0, 0)));
  CHECK(same(parse_expression("lambda2''", jet, mult), jet.lambda(1, 2)));
  CHECK(same(parse_expression("lambda2_d3", jet, mult), jet.lambda(1, 3)));
  CHECK(same(parse_expression("t", jet), jet.time()));
  CHECK(same(parse_expression("k_1", jet), jet.parameter(2)));
}

TEST_CASE("functions", "[scene][parser]") {
  const JetSpace jet = make_jet();
  const ex x = jet.q(0, 0), y = jet.q(1, 0);
  CHECK(same(parse_expression("sin(x)", jet), GiNaC::sin(x)));
  CHECK(same(parse_expression("cos(x)^2 + sin(x)^2 - cos(x)^2", jet), GiNaC::pow(GiNaC::sin(x), 2)));
  CHECK(same(parse_expression("tan(x)", jet), GiNaC::tan(x)));
  CHECK(same(parse_expression("exp(x)*exp(-x)", jet), 1));
  CHECK(same(parse_expression("log(x)", jet), GiNaC::log(x)));
  CHECK(same(parse_expression("sqrt(x)^2", jet), x));
  CHECK(same(parse_expression("abs(x)", jet), GiNaC::abs(x)));
  CHECK(same(parse_expression("sinh(x)", jet), GiNaC::sinh(x)));
  CHECK(same(parse_expression("cosh(x)", jet), GiNaC::cosh(x)));
  CHECK(same(parse_expression("tanh(x)", jet), GiNaC::tanh(x)));
  CHECK(same(parse_expression("asin(x)", jet), GiNaC::asin(x)));
  CHECK(same(parse_expression("acos(x)", jet), GiNaC::acos(x)));
  CHECK(same(parse_expression("atan(x)", jet), GiNaC::atan(x)));
  CHECK(same(parse_expression("atan2(y, x)", jet), GiNaC::atan2(y, x)));
  CHECK(same(parse_expression("sqrt (x'^2 + y'^2)", jet),
             GiNaC::sqrt(GiNaC::pow(jet.q(0, 1), 2) + GiNaC::pow(jet.q(1, 1), 2))));
  CHECK(same(parse_expression("sin(cos(x))", jet), GiNaC::sin(GiNaC::cos(x))));
}

TEST_CASE("constants that GiNaC produces read back", "[scene][parser]") {
  // acos(-1) evaluates to Pi: GiNaC prints it as `Pi`, which must parse back.
  const JetSpace jet = make_jet();
  CHECK(same(parse_expression("acos(-1)", jet), GiNaC::Pi));
  CHECK(same(parse_expression("Pi/4 - atan(1)", jet), 0));
  CHECK(error_offset("sqrt(-4)", jet) == 0);  // complex values have no place in mechanics
  CHECK(error_offset("m + log(-1)", jet) == 4);
}

TEST_CASE("pi and e are constants unless the scene names something so", "[scene][parser]") {
  const JetSpace jet = make_jet();
  const ex t = jet.time(), x = jet.q(0, 0);
  // Checked against the numbers they stand for, not against the parser's own reading of them.
  CHECK(GiNaC::ex_to<GiNaC::numeric>(parse_expression("pi", jet).evalf()).to_double() ==
        Approx(std::acos(-1.0)).epsilon(1e-15));
  CHECK(GiNaC::ex_to<GiNaC::numeric>(parse_expression("e", jet).evalf()).to_double() ==
        Approx(std::exp(1.0)).epsilon(1e-15));
  CHECK(same(parse_expression("sin(2*pi*t)", jet), GiNaC::sin(2 * GiNaC::Pi * t)));
  CHECK(same(parse_expression("e^(-x) - exp(-x)", jet), 0));
  CHECK(same(parse_expression("log(e)", jet), 1));
  CHECK(same(parse_expression("Pi - pi", jet), 0));
  CHECK(error_message("pi'", jet).find("'pi' is a constant") != std::string::npos);
  CHECK(error_message("e''", jet).find("'e' is a constant") != std::string::npos);
  CHECK(error_offset("1 + x*pi'", jet) == 6);
  // Allowed where only parameters are (a [reference] without coordinates, a parameter's value).
  ExpressionRules constants_only;
  constants_only.allow_coordinates = false;
  constants_only.allow_time = false;
  CHECK(same(parse_expression("m*pi/e", jet, constants_only),
             jet.parameter(*jet.parameter_index("m")) * GiNaC::Pi / GiNaC::exp(ex(1))));
  // A scene's own name e or pi keeps its meaning: a coordinate, a parameter, a definition.
  const JetSpace named({"e", "y"}, 0, {"pi"});
  CHECK(same(parse_expression("e' + pi", named), named.q(0, 1) + named.parameter(*named.parameter_index("pi"))));
  ExpressionRules with_definition;
  with_definition.definition = [&](const std::string& name) -> std::optional<nhc::Value> {
    if (name == "e") return nhc::Value::scalar(jet.q(1, 0) * 2);
    return std::nullopt;
  };
  CHECK(same(parse_expression("e", jet, with_definition), 2 * jet.q(1, 0)));
}

TEST_CASE("errors carry the offset of the offending text", "[scene][parser]") {
  const JetSpace jet = make_jet();
  CHECK(error_offset("", jet) == 0);
  CHECK(error_offset("   ", jet) == 3);
  CHECK(error_offset("x +", jet) == 3);
  CHECK(error_offset("x + * y", jet) == 4);
  CHECK(error_offset("(x + y", jet) == 6);
  CHECK(error_offset("x + y)", jet) == 5);
  CHECK(error_offset("2x", jet) == 1);
  CHECK(error_offset("m + foo", jet) == 4);
  CHECK(error_message("m + foo", jet).find("unknown name 'foo'") != std::string::npos);
  CHECK(error_offset("m + foo(x)", jet) == 4);
  CHECK(error_message("m + foo(x)", jet).find("unknown function 'foo'") != std::string::npos);
  CHECK(error_offset("x + m'", jet) == 4);    // primes on a parameter
  CHECK(error_offset("x + t'", jet) == 4);    // primes on t
  CHECK(error_offset("x + t_d1", jet) == 4);  // the jet spelling of t' is just as wrong
  CHECK(error_offset("x + m_d1", jet) == 4);
  CHECK(error_offset("x_d2'", jet) == 0);  // both spellings at once
  CHECK(error_offset("x_d0", jet) == 0);
  CHECK(error_offset("x'''''''''", jet) == 0);  // 9 > kMaxDerivativeOrder
  CHECK(error_offset("x_d1000", jet) == 0);
  CHECK(error_offset("sin(x, y)", jet) == 0);
  CHECK(error_offset("atan2(x)", jet) == 0);
  CHECK(error_offset("sin()", jet) == 4);
  CHECK(error_offset("sin(x", jet) == 5);
  CHECK(error_offset("1/0", jet) == 1);
  CHECK(error_offset("x/(m - m)", jet) == 1);
  CHECK(error_offset("x + 1e", jet) == 4);
  CHECK(error_offset("x + 1e99999", jet) == 4);
  CHECK(error_offset("x $ y", jet) == 2);
  CHECK(error_offset("x''' + lambda1", jet) == 7);               // multipliers not allowed by default
  CHECK(error_offset("lambda3", jet, with_multipliers()) == 0);  // only 2 constraints
  CHECK(error_offset("lambda0", jet, with_multipliers()) == 0);
  ExpressionRules time_only;
  time_only.allow_coordinates = false;
  CHECK(error_offset("t + y", jet, time_only) == 4);
  ExpressionRules no_time;
  no_time.allow_time = false;
  CHECK(error_offset("x + t", jet, no_time) == 4);
}

TEST_CASE("hostile input fails cleanly", "[scene][parser]") {
  const JetSpace jet = make_jet();
  CHECK(error_offset(std::string(100000, '('), jet) == 66);
  CHECK(error_offset(std::string(100000, '-') + "x", jet) == 0);
  std::string tower = "x";
  for (int i = 0; i < 5000; ++i) tower += "^x";
  CHECK(error_offset(tower, jet) == 396);
  CHECK(error_offset(std::string(1000, '9') + "e1", jet) == 0);
  CHECK(error_offset("x\xc3\xa9", jet) == 1);
  CHECK(error_offset(std::string("x\0y", 3), jet) == 1);
  // Deep but legal nesting still parses.
  CHECK(same(parse_expression(std::string(50, '(') + "x" + std::string(50, ')'), jet), jet.q(0, 0)));
}

TEST_CASE("size limits on scene input, not on nhc's own printed output", "[scene][parser]") {
  const JetSpace jet = make_jet();
  // Found by the fuzzers: a tower of symbolic exponents made the normal form hang, products of
  // numbers grew without bound, numbers beyond double range failed only in code generation.
  CHECK(error_offset("x^x^x^x^x^t", jet) == 1);
  CHECK_NOTHROW(parse_expression("x^x^x^x^t", jet));
  CHECK(error_offset("x*1e300*1e300", jet) == 7);
  CHECK(error_offset("2^2000", jet) == 1);
  CHECK(error_offset("(x + x' + t + 1)^64 * (x + t)^64", jet) == 0);       // > 10^4 expanded terms
  CHECK(error_offset("cos((x + x' + t + 1)^64 * (x + t)^64)", jet) == 0);  // also in arguments
  CHECK(error_offset("sqrt((x + x' + t + 1)^64 * (x + t)^64)", jet) == 0);
  std::string product = "x'";
  for (int k = 1; k <= 70; ++k) product += "*sin(" + std::to_string(k) + "*x)";
  CHECK(error_offset(product, jet) == 0);  // more than 64 factors
  CHECK(error_offset(std::string(100001, ' ') + "x", jet) == 0);
  // What nhc prints can exceed them: y^81 from y*(y^4)^20, (1+x)^128 from (1+x)^64*(1+x)^64.
  nhc::ExpressionRules own_output;
  own_output.input_limits = false;
  CHECK(error_offset("x^81", jet) == 1);
  CHECK(same(parse_expression("x^81", jet, own_output), GiNaC::pow(jet.q(0, 0), 81)));
  CHECK_NOTHROW(parse_expression("(1+x)^128", jet, own_output));
  CHECK_NOTHROW(parse_expression(std::string(1300, '7') + "/3", jet, own_output));
}

TEST_CASE("inverse hyperbolic functions, checked against their logarithmic forms", "[scene][parser]") {
  const JetSpace jet = make_jet();
  const ex x = jet.q(0, 0);
  // asinh x = log(x + sqrt(x² + 1)), acosh x = log(x + sqrt(x² − 1)), atanh x = log((1 + x)/(1 − x))/2.
  for (double v : {0.3, -0.7, 0.95}) {
    const GiNaC::exmap at{{x, v}};
    const auto value = [&](const std::string& text) {
      return GiNaC::ex_to<GiNaC::numeric>(parse_expression(text, jet).subs(at).evalf()).to_double();
    };
    CHECK(std::abs(value("asinh(x)") - std::log(v + std::sqrt(v * v + 1))) < 1e-14);
    CHECK(std::abs(value("atanh(x)") - 0.5 * std::log((1 + v) / (1 - v))) < 1e-14);
    CHECK(std::abs(value("acosh(2 + x)") - std::log(2 + v + std::sqrt((2 + v) * (2 + v) - 1))) < 1e-14);
  }
  // Their derivatives, which the models need: d asinh = 1/sqrt(1 + x²) etc.
  CHECK(same(parse_expression("asinh(x)", jet).diff(GiNaC::ex_to<GiNaC::symbol>(x)), 1 / GiNaC::sqrt(1 + x * x)));
  CHECK(same(parse_expression("atanh(x)", jet).diff(GiNaC::ex_to<GiNaC::symbol>(x)), 1 / (1 - x * x)));
}

TEST_CASE("unknown names and operators come with a hint", "[scene][parser]") {
  const JetSpace jet = make_jet();
  CHECK(error_message("x**2", jet).find("powers are written with ^") != std::string::npos);
  CHECK(error_offset("m*x**2", jet) == 3);
  CHECK(error_message("x_dot + y", jet).find("unknown name 'x_dot' (derivatives are written with primes: x')") !=
        std::string::npos);
  CHECK(error_message("xdot", jet).find("primes: x'") != std::string::npos);
  CHECK(error_message("theta_ddot", jet).find("primes: theta''") != std::string::npos);
  CHECK(error_message("dtheta", jet).find("primes: theta'") != std::string::npos);
  CHECK(error_message("lambda3", jet).find("the multipliers are lambda1 to lambda2") != std::string::npos);
  CHECK(error_message("thetta", jet).find("did you mean 'theta'?") != std::string::npos);
  CHECK(error_message("k1", jet).find("did you mean 'k_1'?") != std::string::npos);
  CHECK(error_message("zzz", jet).find("(") == std::string::npos);  // nothing close: no hint
}

TEST_CASE("0 to a non-numeric power is refused where it is written", "[scene][parser]") {
  // Found by scripts/fuzz_long.sh: rotz(x^-0^y') differentiated 0^y', whose derivative holds
  // log(0), and GiNaC's "division by zero" ended nhc as an internal error.
  const JetSpace jet = make_jet();
  CHECK(error_message("x + 0^y", jet).find("0 to a power that is not a positive number is undefined") !=
        std::string::npos);
  CHECK(error_offset("x + 0^y", jet) == 5);
  CHECK(error_message("rotz(x^-0^y')[1, 1]", jet).find("0 to a power") != std::string::npos);
  CHECK(error_offset("0^(-1)", jet) == 1);
  CHECK(parse_expression("0^2 + x", jet).is_equal(jet.q(0, 0)));
}

TEST_CASE("a symbol of q()'s result is the jet space's own, alive as long as the space", "[scene]") {
  // A reference into q()'s ex outlives the ex: the sliding model of a contact differentiated
  // by such a reference, and read freed memory when q() handed out a copy of its own.
  const JetSpace jet = make_jet();
  const GiNaC::symbol& v = GiNaC::ex_to<GiNaC::symbol>(jet.q(2, 1));
  REQUIRE(&v == &jet.symbol({nhc::VariableKind::coordinate, 2, 1}));
  CHECK((jet.q(0, 1) - jet.parameter(0) * jet.q(2, 1)).diff(v).is_equal(-jet.parameter(0)));
  CHECK(&GiNaC::ex_to<GiNaC::symbol>(jet.lambda(1, 0)) == &jet.symbol({nhc::VariableKind::multiplier, 1, 0}));
}
