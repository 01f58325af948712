#include "nhc/emit/cse.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>
#include <tuple>

#include "nhc/errors.hpp"

namespace nhc {

namespace {

/// Exponents up to this are multiplied out (GiNaC's power.cpp does the same "to aid compiler
/// CSE"); larger ones go through std::pow.
constexpr int kLargestExpandedPower = 4;

std::string describe(const GiNaC::ex& e) {
  std::ostringstream out;
  out << e;
  return out.str();
}

/// Bit pattern of a double, so that hash-consing tells −0.0 from 0.0 and never compares NaNs.
unsigned long long bits_of(double v) {
  unsigned long long b = 0;
  static_assert(sizeof b == sizeof v);
  std::memcpy(&b, &v, sizeof b);
  return b;
}

double to_real(const GiNaC::numeric& n, const GiNaC::ex& context) {
  if (!n.is_real())
    throw MathError("cannot generate code for a complex number in " + describe(context));
  return n.to_double();
}

/// GiNaC functions with a C++ counterpart of the same arity.
const std::map<std::string, std::string>& cpp_functions() {
  static const std::map<std::string, std::string> table = {
      {"sin", "std::sin"},     {"cos", "std::cos"},     {"tan", "std::tan"},
      {"exp", "std::exp"},     {"log", "std::log"},     {"sinh", "std::sinh"},
      {"cosh", "std::cosh"},   {"tanh", "std::tanh"},   {"asin", "std::asin"},
      {"acos", "std::acos"},   {"atan", "std::atan"},   {"asinh", "std::asinh"},
      {"acosh", "std::acosh"}, {"atanh", "std::atanh"}, {"abs", "std::fabs"},
      {"atan2", "std::atan2"},
  };
  return table;
}

}  // namespace

bool Instruction::operator<(const Instruction& o) const {
  return std::make_tuple(op, std::cref(args), std::cref(negated), bits_of(value), exponent,
                         std::cref(name)) <
         std::make_tuple(o.op, std::cref(o.args), std::cref(o.negated), bits_of(o.value),
                         o.exponent, std::cref(o.name));
}

ExpressionDag::ExpressionDag(std::map<GiNaC::ex, std::string, GiNaC::ex_is_less> inputs)
    : inputs_(std::move(inputs)) {}

int ExpressionDag::add(const GiNaC::ex& e) { return lower(e); }

int ExpressionDag::make(Instruction instruction) {
  auto it = by_instruction_.find(instruction);
  if (it != by_instruction_.end()) return it->second;
  const int id = size();
  by_instruction_.emplace(instruction, id);
  instructions_.push_back(std::move(instruction));
  return id;
}

int ExpressionDag::constant(double value) {
  Instruction c;
  c.op = OpCode::constant;
  c.value = value;
  return make(std::move(c));
}

int ExpressionDag::make_product(std::vector<int> factors) {
  if (factors.empty()) return constant(1.0);
  if (factors.size() == 1) return factors.front();
  // Operand order is canonical (by index), so equal products hash-cons; constants, created
  // first, usually lead.
  std::sort(factors.begin(), factors.end());
  Instruction p;
  p.op = OpCode::product;
  p.args = std::move(factors);
  return make(std::move(p));
}

int ExpressionDag::make_power(int base, int exponent) {
  if (exponent == 1) return base;
  Instruction p;
  if (exponent <= kLargestExpandedPower) {
    p.op = OpCode::integer_power;
    p.args = {base};
    p.exponent = exponent;
  } else {
    p.op = OpCode::call;
    p.name = "std::pow";
    p.args = {base, constant(static_cast<double>(exponent))};
  }
  return make(std::move(p));
}

std::pair<int, bool> ExpressionDag::lower_signed(const GiNaC::ex& e) {
  if (GiNaC::is_exactly_a<GiNaC::numeric>(e)) {
    const double v = to_real(GiNaC::ex_to<GiNaC::numeric>(e), e);
    return {constant(std::fabs(v)), v < 0};
  }
  if (GiNaC::is_exactly_a<GiNaC::mul>(e)) {
    GiNaC::numeric c = 1;
    for (size_t k = 0; k < e.nops(); ++k)
      if (GiNaC::is_exactly_a<GiNaC::numeric>(e.op(k))) c *= GiNaC::ex_to<GiNaC::numeric>(e.op(k));
    if (c.is_real() && c.is_negative()) return {lower(-e), true};
  }
  return {lower(e), false};
}

int ExpressionDag::lower(const GiNaC::ex& e) {
  auto found = by_expression_.find(e);
  if (found != by_expression_.end()) return found->second;

  int id = -1;
  if (GiNaC::is_exactly_a<GiNaC::numeric>(e)) {
    id = constant(to_real(GiNaC::ex_to<GiNaC::numeric>(e), e));
  } else if (GiNaC::is_a<GiNaC::symbol>(e)) {
    auto it = inputs_.find(e);
    if (it == inputs_.end())
      throw MathError("cannot generate code: " + describe(e) +
                      " is not an input of the generated function");
    Instruction in;
    in.op = OpCode::input;
    in.name = it->second;
    id = make(std::move(in));
  } else if (GiNaC::is_a<GiNaC::constant>(e)) {
    id = constant(to_real(GiNaC::ex_to<GiNaC::numeric>(e.evalf()), e));
  } else if (GiNaC::is_exactly_a<GiNaC::add>(e)) {
    std::vector<std::pair<int, bool>> terms;
    for (size_t k = 0; k < e.nops(); ++k) terms.push_back(lower_signed(e.op(k)));
    // Added terms first, then subtracted ones: a + b − c rather than −c + a + b.
    std::stable_partition(terms.begin(), terms.end(),
                          [](const std::pair<int, bool>& t) { return !t.second; });
    if (terms.front().second) {
      // Every term negative: −(a + b).
      for (auto& t : terms) t.second = false;
      Instruction s;
      s.op = OpCode::sum;
      for (auto& [arg, neg] : terms) {
        s.args.push_back(arg);
        s.negated.push_back(neg);
      }
      Instruction n;
      n.op = OpCode::negate;
      n.args = {make(std::move(s))};
      id = make(std::move(n));
    } else {
      Instruction s;
      s.op = OpCode::sum;
      for (auto& [arg, neg] : terms) {
        s.args.push_back(arg);
        s.negated.push_back(neg);
      }
      id = make(std::move(s));
    }
  } else if (GiNaC::is_exactly_a<GiNaC::mul>(e) || GiNaC::is_exactly_a<GiNaC::power>(e)) {
    auto [magnitude, negative] = lower_signed(e);
    if (!negative) {
      id = lower_product(e);
    } else {
      Instruction n;
      n.op = OpCode::negate;
      n.args = {magnitude};
      id = make(std::move(n));
    }
  } else if (GiNaC::is_a<GiNaC::function>(e)) {
    id = lower_function(e);
  } else {
    throw MathError("cannot generate code for " + describe(e));
  }
  by_expression_.emplace(e, id);
  return id;
}

int ExpressionDag::lower_product(const GiNaC::ex& e) {
  std::vector<GiNaC::ex> factors;
  if (GiNaC::is_exactly_a<GiNaC::mul>(e))
    for (size_t k = 0; k < e.nops(); ++k) factors.push_back(e.op(k));
  else
    factors.push_back(e);

  std::vector<int> numerator, denominator;
  for (const GiNaC::ex& f : factors) {
    if (GiNaC::is_exactly_a<GiNaC::numeric>(f)) {
      const double c = to_real(GiNaC::ex_to<GiNaC::numeric>(f), e);
      if (c != 1.0) numerator.push_back(constant(c));
      continue;
    }
    if (!GiNaC::is_exactly_a<GiNaC::power>(f)) {
      numerator.push_back(lower(f));
      continue;
    }
    const GiNaC::ex base = f.op(0), exponent = f.op(1);
    if (!GiNaC::is_exactly_a<GiNaC::numeric>(exponent) ||
        !GiNaC::ex_to<GiNaC::numeric>(exponent).is_rational()) {
      Instruction p;
      p.op = OpCode::call;
      p.name = "std::pow";
      p.args = {lower(base), lower(exponent)};
      numerator.push_back(make(std::move(p)));
      continue;
    }
    const GiNaC::numeric q = GiNaC::ex_to<GiNaC::numeric>(exponent);
    const GiNaC::numeric num = q.numer(), den = q.denom();
    auto& side = q.is_negative() ? denominator : numerator;
    if (den == 1 && GiNaC::abs(num) <= 64) {
      side.push_back(make_power(lower(base), GiNaC::abs(num).to_int()));
    } else if (den == 2 && GiNaC::abs(num) <= 64) {
      // b^(k/2) = b^((k−1)/2) · sqrt(b): the sqrt is shared by every half-integer power of b.
      const int whole = (GiNaC::abs(num).to_int() - 1) / 2;
      const int b = lower(base);
      if (whole > 0) side.push_back(make_power(b, whole));
      Instruction s;
      s.op = OpCode::square_root;
      s.args = {b};
      side.push_back(make(std::move(s)));
    } else {
      Instruction p;
      p.op = OpCode::call;
      p.name = "std::pow";
      p.args = {lower(base), constant(to_real(q, e))};
      numerator.push_back(make(std::move(p)));
    }
  }
  const int top = make_product(std::move(numerator));
  if (denominator.empty()) return top;
  Instruction d;
  d.op = OpCode::quotient;
  d.args = {top, make_product(std::move(denominator))};
  return make(std::move(d));
}

int ExpressionDag::lower_function(const GiNaC::ex& e) {
  const auto& f = GiNaC::ex_to<GiNaC::function>(e);
  const std::string name = f.get_name();
  Instruction c;
  for (size_t k = 0; k < e.nops(); ++k) c.args.push_back(lower(e.op(k)));
  if (name == "csgn" && c.args.size() == 1) {
    c.op = OpCode::sign;
  } else if (name == "step" && c.args.size() == 1) {
    c.op = OpCode::step;
  } else {
    auto it = cpp_functions().find(name);
    if (it == cpp_functions().end())
      throw MathError("cannot generate code for the function " + name + " in " + describe(e));
    c.op = OpCode::call;
    c.name = it->second;
  }
  return make(std::move(c));
}

std::vector<int> ExpressionDag::reachable(const std::vector<int>& outputs) const {
  std::vector<char> seen(instructions_.size(), 0);
  std::vector<int> stack(outputs.begin(), outputs.end());
  while (!stack.empty()) {
    const int id = stack.back();
    stack.pop_back();
    if (seen[static_cast<size_t>(id)]) continue;
    seen[static_cast<size_t>(id)] = 1;
    for (int a : (*this)[id].args) stack.push_back(a);
  }
  std::vector<int> ids;
  for (int id = 0; id < size(); ++id)
    if (seen[static_cast<size_t>(id)]) ids.push_back(id);
  return ids;
}

OperationCount& OperationCount::operator+=(const OperationCount& o) {
  additions += o.additions;
  multiplications += o.multiplications;
  divisions += o.divisions;
  calls += o.calls;
  return *this;
}

OperationCount instruction_cost(const Instruction& in) {
  OperationCount c;
  const auto arity = static_cast<long long>(in.args.size());
  switch (in.op) {
    case OpCode::constant:
    case OpCode::input:
      break;
    case OpCode::sum:
      c.additions = arity - 1;
      break;
    case OpCode::negate:
      c.additions = 1;
      break;
    case OpCode::product:
      c.multiplications = arity - 1;
      break;
    case OpCode::quotient:
      c.divisions = 1;
      break;
    case OpCode::integer_power:
      c.multiplications = in.exponent - 1;
      break;
    case OpCode::square_root:
    case OpCode::call:
    case OpCode::sign:
    case OpCode::step:
      c.calls = 1;
      break;
  }
  return c;
}

OperationCount tree_operation_count(const ExpressionDag& dag, const std::vector<int>& outputs) {
  // Tree cost of every instruction, bottom up (operands precede their users).
  std::vector<OperationCount> tree(static_cast<size_t>(dag.size()));
  for (int id = 0; id < dag.size(); ++id) {
    OperationCount c = instruction_cost(dag[id]);
    const Instruction& in = dag[id];
    // x^k multiplied out evaluates its base once per factor when there is no CSE.
    const int uses = in.op == OpCode::integer_power ? in.exponent : 1;
    for (int a : in.args)
      for (int u = 0; u < uses; ++u) c += tree[static_cast<size_t>(a)];
    tree[static_cast<size_t>(id)] = c;
  }
  OperationCount total;
  for (int o : outputs) total += tree[static_cast<size_t>(o)];
  return total;
}

OperationCount dag_operation_count(const ExpressionDag& dag, const std::vector<int>& outputs) {
  OperationCount total;
  for (int id : dag.reachable(outputs)) total += instruction_cost(dag[id]);
  return total;
}

}  // namespace nhc
