// The CSE pass and the C++ printer on tiny expressions: exact text for a few cases (Drake's
// codegen_test habit), sharing, operation counts, and exact round trip of constants.
#include <catch2/catch.hpp>
#include <ginac/ginac.h>

#include <cmath>
#include <cstdlib>
#include <map>
#include <random>
#include <string>

#include "nhc/expr/cpp_printer.hpp"
#include "nhc/expr/common_arguments.hpp"
#include "nhc/expr/common_factors.hpp"
#include "nhc/expr/expression_dag.hpp"
#include "nhc/errors.hpp"
#include "nhc/expr/intermediate.hpp"

namespace {

using GiNaC::ex;

struct Fixture {
  GiNaC::realsymbol x{"x"}, y{"y"}, t{"t"}, a{"a"};
  nhc::ExpressionDag dag{{{x, "y[0]"}, {y, "y[1]"}, {t, "t"}, {a, "p[0]"}}};

  std::string print(const ex& e) { return nhc::print_cpp_expression(dag, dag.add(e)); }
  std::string block(const std::vector<ex>& outputs) {
    std::vector<nhc::Assignment> assignments;
    for (size_t k = 0; k < outputs.size(); ++k)
      assignments.push_back({"r[" + std::to_string(k) + "]", dag.add(outputs[k]), ""});
    return nhc::print_cpp_block(dag, assignments, "").code;
  }
};

}  // namespace

TEST_CASE("double literals round-trip exactly", "[codegen]") {
  CHECK(nhc::cpp_double_literal(2.0) == "2.0");
  CHECK(nhc::cpp_double_literal(0.5) == "0.5");
  CHECK(nhc::cpp_double_literal(0.1) == "0.10000000000000001");
  CHECK(nhc::cpp_double_literal(-1e-300) == "-1e-300");
  CHECK(nhc::cpp_double_literal(1.0 / 3.0) == "0.33333333333333331");
  CHECK(nhc::cpp_double_literal(0.0) == "0.0");
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> mantissa(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-300, 300);
  for (int k = 0; k < 2000; ++k) {
    const double v = std::ldexp(mantissa(rng), exponent(rng));
    CHECK(std::strtod(nhc::cpp_double_literal(v).c_str(), nullptr) == v);
  }
  CHECK_THROWS_AS(nhc::cpp_double_literal(std::numeric_limits<double>::infinity()), nhc::MathError);
}

TEST_CASE("powers, quotients and signs print as C++", "[codegen]") {
  Fixture f;
  CHECK(f.print(GiNaC::pow(f.x, 2)) == "y[0] * y[0]");
  CHECK(f.print(GiNaC::pow(f.x, 3)) == "y[0] * y[0] * y[0]");
  CHECK(f.print(GiNaC::pow(f.x, 7)) == "std::pow(y[0], 7.0)");
  CHECK(f.print(GiNaC::pow(f.x, -1)) == "1.0 / y[0]");
  CHECK(f.print(GiNaC::sqrt(f.x)) == "std::sqrt(y[0])");
  CHECK(f.print(GiNaC::pow(f.x, GiNaC::numeric(1, 3))) == "std::pow(y[0], 0.33333333333333331)");
  CHECK(f.print(f.y / f.x) == "y[1] / y[0]");
  CHECK(f.print(-f.y / f.x) == "-(y[1] / y[0])");
  CHECK(f.print(f.x - f.y) == "y[0] - y[1]");
  CHECK(f.print(f.t * f.a + 1) == "1.0 + t * p[0]");
  CHECK(f.print(GiNaC::sin(f.x + f.y)) == "std::sin(y[1] + y[0])");
  CHECK(f.print(GiNaC::abs(f.x)) == "std::fabs(y[0])");
  CHECK(f.print(GiNaC::atan2(f.y, f.x)) == "std::atan2(y[1], y[0])");
  // b^(-3/2) = 1 / (b sqrt(b)): the square root is shared with every other half power of b.
  const ex b = f.x * f.x + f.y * f.y;
  const std::string text = f.block({GiNaC::pow(b, GiNaC::numeric(-3, 2)), GiNaC::sqrt(b)});
  CHECK(text ==
        "const double w0 = y[1] * y[1] + y[0] * y[0];\n"
        "const double w1 = std::sqrt(w0);\n"
        "r[0] = 1.0 / (w1 * w0);\n"
        "r[1] = w1;\n");
}

TEST_CASE("the printed code does not depend on GiNaC's term order", "[codegen]") {
  // GiNaC orders terms by hashes that follow object addresses, so the same expression may come
  // in a different order, or with its signs distributed differently, in another run.
  Fixture f;
  const std::string a = f.print(-(f.x - f.y) / (f.t - f.a));
  const std::string b = f.print((f.y - f.x) / (f.t - f.a));
  const std::string c = f.print((f.x - f.y) / (f.a - f.t));
  CHECK(a == b);
  CHECK(b == c);
  Fixture g;  // the same expressions over new symbols, in a new DAG
  CHECK(g.print((g.x - g.y) / (g.a - g.t)) == c);
}

TEST_CASE("a subexpression shared between outputs becomes one temporary", "[codegen]") {
  Fixture f;
  const ex s = GiNaC::sin(f.x * f.y);
  const std::string text = f.block({s + f.t, s * f.a, GiNaC::cos(f.x)});
  CHECK(text ==
        "const double w0 = std::sin(y[1] * y[0]);\n"
        "r[0] = t + w0;\n"
        "r[1] = p[0] * w0;\n"
        "r[2] = std::cos(y[0]);\n");
  // A power multiplied out reads its base repeatedly, so the base is a temporary.
  Fixture g;
  CHECK(g.block({GiNaC::pow(g.x + g.y, 2)}) ==
        "const double w0 = y[1] + y[0];\n"
        "r[0] = w0 * w0;\n");
}

TEST_CASE("hash-consing on GiNaC's hash and is_equal", "[codegen]") {
  Fixture f;
  const int first = f.dag.add(GiNaC::sqrt(f.x * f.x + 1) * f.a);
  const int size = f.dag.size();
  // The same expression built again (a distinct GiNaC object) lowers to the same instruction.
  CHECK(f.dag.add(f.a * GiNaC::sqrt(1 + GiNaC::pow(f.x, 2))) == first);
  CHECK(f.dag.size() == size);
  // Instructions are topologically sorted.
  for (int id = 0; id < f.dag.size(); ++id)
    for (int arg : f.dag[id].args) CHECK(arg < id);
}

TEST_CASE("operation counts before and after CSE", "[codegen]") {
  Fixture f;
  const ex s = GiNaC::sqrt(f.x * f.x + f.y * f.y);
  std::vector<int> outputs = {f.dag.add(f.x / s), f.dag.add(f.y / s), f.dag.add(s * f.t)};
  const nhc::OperationCount tree = nhc::tree_operation_count(f.dag, outputs);
  const nhc::OperationCount dag = nhc::dag_operation_count(f.dag, outputs);
  // Each use of s costs 2 multiplications, 1 addition, 1 sqrt as a tree.
  CHECK(tree.calls == 3);
  CHECK(tree.multiplications == 3 * 2 + 1);
  CHECK(tree.additions == 3);
  CHECK(tree.divisions == 2);
  CHECK(dag.calls == 1);
  CHECK(dag.multiplications == 2 + 1);
  CHECK(dag.additions == 1);
  CHECK(dag.divisions == 2);
  CHECK(dag.total() < tree.total());
}

TEST_CASE("expressions without a C++ counterpart are refused", "[codegen]") {
  Fixture f;
  GiNaC::realsymbol stranger("stranger");
  CHECK_THROWS_AS(f.dag.add(f.x + stranger), nhc::MathError);
  CHECK_THROWS_AS(f.dag.add(f.x + GiNaC::I), nhc::MathError);
  CHECK_THROWS_AS(f.dag.add(GiNaC::zeta(f.x)), nhc::MathError);
}

TEST_CASE("named intermediates are lowered once each, in proportion to the structure", "[codegen][intermediate]") {
  // The definition chain d0 = x' + y + 1, d_k = d_{k-1}^2 + x over the functions' inputs: 24
  // squarings and 24 additions, not the 2^24-degree expansion.
  Fixture f;
  const ex q = f.x, qd = f.y;
  ex d = nhc::Intermediate("d0", "d_0", qd + f.t + 1);
  for (int k = 1; k <= 24; ++k) d = nhc::Intermediate("d" + std::to_string(k), "d", d * d + q);
  const int once = f.dag.add(d);
  const int twice = f.dag.add(d * f.a + d);
  const nhc::OperationCount count = nhc::dag_operation_count(f.dag, {once, twice});
  CHECK(count.multiplications == 24 + 1);  // each d_{k-1}^2, then d24 * p[0]
  CHECK(count.additions == 2 + 24 + 1);    // d0, each + q, then + d24
  CHECK(nhc::dag_operation_count(f.dag, {once}).total() == 2 + 24 + 24);
  // A chain of 3000 links lowers without recursing once per link.
  ex c = nhc::Intermediate("c0", "c_0", q);
  for (int k = 1; k <= 3000; ++k) c = nhc::Intermediate("c" + std::to_string(k), "c", c * q + f.t);
  CHECK(nhc::dag_operation_count(f.dag, {f.dag.add(c)}).total() == 2 * 3000);
}

namespace {

/// The DAG's value of instruction `id` with y[0] = x, y[1] = y, t, p[0] = a: a plain interpreter
/// for the instructions these tests produce.
double value_of(const nhc::ExpressionDag& dag, int id, const std::map<std::string, double>& inputs) {
  const nhc::Instruction& in = dag[id];
  switch (in.op) {
    case nhc::OpCode::constant:
      return in.value;
    case nhc::OpCode::input:
      return inputs.at(in.name);
    case nhc::OpCode::sum: {
      double s = 0;
      for (std::size_t k = 0; k < in.args.size(); ++k)
        s += (in.negated[k] ? -1 : 1) * value_of(dag, in.args[k], inputs);
      return s;
    }
    case nhc::OpCode::product: {
      double p = 1;
      for (int a : in.args) p *= value_of(dag, a, inputs);
      return p;
    }
    case nhc::OpCode::quotient:
      return value_of(dag, in.args[0], inputs) / value_of(dag, in.args[1], inputs);
    case nhc::OpCode::negate:
      return -value_of(dag, in.args[0], inputs);
    case nhc::OpCode::integer_power:
      return std::pow(value_of(dag, in.args[0], inputs), in.exponent);
    case nhc::OpCode::call:
      if (in.name == "std::sin") return std::sin(value_of(dag, in.args[0], inputs));
      break;
    default:
      break;
  }
  FAIL("unexpected instruction " << in.name);
  return 0;
}

}  // namespace

TEST_CASE("pairs common to several sums or products are computed once", "[codegen][common-arguments]") {
  Fixture f;
  const ex& x = f.x;
  const ex& y = f.y;
  const ex& a = f.a;
  const ex& t = f.t;
  // x·y in two products, x − y in two sums (once as y − x), and one product that is x·y itself.
  const std::vector<ex> expressions = {x * y * a, x * y * GiNaC::sin(t), x - y + a, y - x + t * t, 3 * x * y};
  std::vector<int> outputs;
  for (const ex& e : expressions) outputs.push_back(f.dag.add(e));
  const nhc::OperationCount before = nhc::dag_operation_count(f.dag, outputs);
  const nhc::ExpressionDag shared = nhc::share_common_arguments(f.dag, outputs);
  const nhc::OperationCount after = nhc::dag_operation_count(shared, outputs);
  // Before: 2 + 2 + 1 (sin) + 2 + 3 (t² is one) + 2 = 12. After: x·y once (1), used by three
  // products (1 each), sin (1), x − y once (1), used by two sums (1 each), t² (1) = 9.
  CHECK(before.total() == 12);
  CHECK(after.total() == 9);
  // The same values, against GiNaC's own evaluation of the expressions.
  const std::map<std::string, double> inputs = {{"y[0]", 0.7}, {"y[1]", -1.3}, {"t", 0.4}, {"p[0]", 2.1}};
  const GiNaC::exmap point = {{x, 0.7}, {y, -1.3}, {t, 0.4}, {a, 2.1}};
  for (std::size_t k = 0; k < expressions.size(); ++k) {
    INFO(expressions[k]);
    const double expected = GiNaC::ex_to<GiNaC::numeric>(expressions[k].subs(point).evalf()).to_double();
    CHECK(value_of(shared, outputs[k], inputs) == Approx(expected).epsilon(1e-15));
  }
}

TEST_CASE("a factor over a common denominator is one quotient, as SymPy's opt_cse finds it",
          "[codegen][common-arguments]") {
  Fixture f;
  const ex& x = f.x;
  const ex& y = f.y;
  const ex& a = f.a;
  const ex& t = f.t;
  // x·a/(y² + 1) over a different factor each time (Appell–Hamel's residual has y₆·p₁/w₁ so).
  const ex w = y * y + 1;
  const std::vector<ex> expressions = {x * a * t / w, x * a * GiNaC::sin(t) / w, x * a * y / w};
  std::vector<int> outputs;
  for (const ex& e : expressions) outputs.push_back(f.dag.add(e));
  const nhc::OperationCount before = nhc::dag_operation_count(f.dag, outputs);
  const nhc::ExpressionDag shared = nhc::share_common_arguments(f.dag, outputs);
  const nhc::OperationCount after = nhc::dag_operation_count(shared, outputs);
  // Before: w (2), sin (1), three quotients of three factors (3 each) = 12. After: w (2), sin (1),
  // x·a/w once (2: a pair, then the pair over w), times the other factor (1 each) = 8; sharing
  // only products, x·a (1) and then (x·a·factor)/w (2 each) would be 10.
  CHECK(before.total() == 12);
  CHECK(after.total() == 8);
  CHECK(after.divisions == 1);
  const std::map<std::string, double> inputs = {{"y[0]", 0.7}, {"y[1]", -1.3}, {"t", 0.4}, {"p[0]", 2.1}};
  const GiNaC::exmap point = {{x, 0.7}, {y, -1.3}, {t, 0.4}, {a, 2.1}};
  for (std::size_t k = 0; k < expressions.size(); ++k) {
    INFO(expressions[k]);
    const double expected = GiNaC::ex_to<GiNaC::numeric>(expressions[k].subs(point).evalf()).to_double();
    CHECK(value_of(shared, outputs[k], inputs) == Approx(expected).epsilon(1e-15));
  }
}

TEST_CASE("a factor common to several terms of a sum is taken out of them", "[codegen][common-factors]") {
  Fixture f;
  const ex& x = f.x;
  const ex& y = f.y;
  const ex& a = f.a;
  const ex& t = f.t;
  // Like the knife chain's D f: y·x·sin t + a·sin a·x − t·sin a; and x·y + a·x·t where x·y is
  // an output itself (so that it stays one product and is not taken apart).
  const std::vector<ex> expressions = {y * x * GiNaC::sin(t) + a * GiNaC::sin(a) * x - t * GiNaC::sin(a),
                                       x * y + a * x * t, x * y};
  std::vector<int> outputs;
  for (const ex& e : expressions) outputs.push_back(f.dag.add(e));
  const nhc::OperationCount before = nhc::dag_operation_count(f.dag, outputs);
  const nhc::ExpressionDag factored = nhc::factor_common_terms(f.dag, outputs);
  const nhc::OperationCount after = nhc::dag_operation_count(factored, outputs);
  // First sum: x (or sin a) out of two of its terms, one multiplication fewer. Second: x·y is
  // shared (the third output), so only a·x·t is a product that may be taken apart: no change.
  CHECK(after.total() == before.total() - 1);
  const std::map<std::string, double> inputs = {{"y[0]", 0.7}, {"y[1]", -1.3}, {"t", 0.4}, {"p[0]", 2.1}};
  const GiNaC::exmap point = {{x, 0.7}, {y, -1.3}, {t, 0.4}, {a, 2.1}};
  for (std::size_t k = 0; k < expressions.size(); ++k) {
    INFO(expressions[k]);
    const double expected = GiNaC::ex_to<GiNaC::numeric>(expressions[k].subs(point).evalf()).to_double();
    CHECK(value_of(factored, outputs[k], inputs) == Approx(expected).epsilon(1e-15));
  }
}
