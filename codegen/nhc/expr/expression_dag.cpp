#include "nhc/expr/expression_dag.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>
#include <tuple>

#include "nhc/errors.hpp"
#include "nhc/expr/intermediate.hpp"
#include "nhc/long_work.hpp"

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
  if (!n.is_real()) throw MathError("cannot generate code for a complex number in " + describe(context));
  return n.to_double();
}

/// GiNaC functions with a C++ counterpart of the same arity.
const std::map<std::string, std::string>& cpp_functions() {
  static const std::map<std::string, std::string> table = {
      {"sin", "std::sin"},     {"cos", "std::cos"},     {"tan", "std::tan"},   {"exp", "std::exp"},
      {"log", "std::log"},     {"sinh", "std::sinh"},   {"cosh", "std::cosh"}, {"tanh", "std::tanh"},
      {"asin", "std::asin"},   {"acos", "std::acos"},   {"atan", "std::atan"}, {"asinh", "std::asinh"},
      {"acosh", "std::acosh"}, {"atanh", "std::atanh"}, {"abs", "std::fabs"},  {"atan2", "std::atan2"},
  };
  return table;
}

/// FNV-1a: std::hash<std::string> is not specified to be stable.
std::uint64_t hash_text(const std::string& text) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (unsigned char c : text) h = (h ^ c) * 0x100000001b3ULL;
  return h;
}

}  // namespace

std::uint64_t mix_keys(std::uint64_t seed, std::uint64_t value) {
  std::uint64_t z = seed ^ (value + 0x9e3779b97f4a7c15ULL + (seed << 6) + (seed >> 2));
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

bool Instruction::operator<(const Instruction& o) const {
  return std::make_tuple(op, std::cref(args), std::cref(negated), bits_of(value), exponent, std::cref(name)) <
         std::make_tuple(o.op, std::cref(o.args), std::cref(o.negated), bits_of(o.value), o.exponent,
                         std::cref(o.name));
}

ExpressionDag::ExpressionDag(std::map<GiNaC::ex, std::string, GiNaC::ex_is_less> inputs) : inputs_(std::move(inputs)) {}

int ExpressionDag::add(const GiNaC::ex& e) {
  // Named intermediates first, each once and in dependency order (each after those it uses):
  // one instruction per intermediate, shared by every output, and no recursion per link of a
  // chain of definitions when e is lowered.
  for (const GiNaC::ex& d : intermediates_in_order({e}))
    if (!by_expression_.count(d) && !inputs_.count(d))
      by_expression_.emplace(d, lower_signed(intermediate_expression(d)));
  return lower(e);
}

const GiNaC::ex& ExpressionDag::intermediate_expression(const GiNaC::ex& d) {
  return GiNaC::ex_to<Intermediate>(d).expression();
}

int ExpressionDag::make(Instruction instruction) {
  // Canonical operand order for the commutative operations: by structural key (then index,
  // for the astronomically unlikely equal keys); added terms before subtracted ones.
  auto key_of = [this](int id) { return instructions_[static_cast<size_t>(id)].key; };
  if (instruction.op == OpCode::product) {
    std::sort(instruction.args.begin(), instruction.args.end(),
              [&](int a, int b) { return std::make_pair(key_of(a), a) < std::make_pair(key_of(b), b); });
  } else if (instruction.op == OpCode::sum) {
    std::vector<std::pair<bool, int>> terms;
    for (size_t k = 0; k < instruction.args.size(); ++k)
      terms.emplace_back(instruction.negated[k], instruction.args[k]);
    std::sort(terms.begin(), terms.end(), [&](const auto& a, const auto& b) {
      return std::make_tuple(a.first, key_of(a.second), a.second) <
             std::make_tuple(b.first, key_of(b.second), b.second);
    });
    for (size_t k = 0; k < terms.size(); ++k) {
      instruction.negated[k] = terms[k].first;
      instruction.args[k] = terms[k].second;
    }
  }
  std::uint64_t key = mix_keys(static_cast<std::uint64_t>(instruction.op) + 1, hash_text(instruction.name));
  key = mix_keys(key, bits_of(instruction.value));
  key = mix_keys(key, static_cast<std::uint64_t>(instruction.exponent));
  for (size_t k = 0; k < instruction.args.size(); ++k) {
    key = mix_keys(key, key_of(instruction.args[k]));
    if (instruction.op == OpCode::sum) key = mix_keys(key, instruction.negated[k] ? 2 : 1);
  }
  instruction.key = key;

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

int ExpressionDag::negated(int id) {
  Instruction in = (*this)[id];
  switch (in.op) {
    case OpCode::sum:
      for (size_t k = 0; k < in.negated.size(); ++k) in.negated[k] = !in.negated[k];
      return make(std::move(in));
    case OpCode::quotient: {
      const int numerator = negated(in.args[0]);
      if (numerator < 0) return -1;
      in.args[0] = numerator;
      return make(std::move(in));
    }
    case OpCode::product:
      for (int& arg : in.args)
        if ((*this)[arg].op == OpCode::sum) {
          arg = negated(arg);
          return make(std::move(in));
        }
      return -1;
    default:
      return -1;
  }
}

int ExpressionDag::lower(const GiNaC::ex& e) {
  const auto [magnitude, negative] = lower_signed(e);
  if (!negative) return magnitude;
  if ((*this)[magnitude].op == OpCode::constant) return constant(-(*this)[magnitude].value);
  // −(a − b)/c is printed (b − a)/c; a negation is left only where no sum can take the sign.
  const int absorbed = negated(magnitude);
  if (absorbed >= 0) return absorbed;
  Instruction n;
  n.op = OpCode::negate;
  n.args = {magnitude};
  return make(std::move(n));
}

// Signs are pulled out of sums and products and normalised, so that forms GiNaC may produce
// for the same value in different runs, such as −(a − b)/c and (b − a)/c, lower alike.
std::pair<int, bool> ExpressionDag::lower_signed(const GiNaC::ex& e) {
  check_for_stop();  // the stop question of long work (nhc/long_work.hpp): lowering is per node
  auto found = by_expression_.find(e);
  if (found != by_expression_.end()) return found->second;

  std::pair<int, bool> result{-1, false};
  if (GiNaC::is_exactly_a<GiNaC::numeric>(e)) {
    const double v = to_real(GiNaC::ex_to<GiNaC::numeric>(e), e);
    result = {constant(std::fabs(v)), v < 0};
  } else if (is_intermediate(e) && !inputs_.count(e)) {
    result = lower_signed(intermediate_expression(e));  // add() lowers them first; this is its fallback
  } else if (GiNaC::is_a<GiNaC::symbol>(e)) {
    auto it = inputs_.find(e);
    if (it == inputs_.end())
      throw MathError("cannot generate code: " + describe(e) + " is not an input of the generated function");
    Instruction in;
    in.op = OpCode::input;
    in.name = it->second;
    result = {make(std::move(in)), false};
  } else if (GiNaC::is_a<GiNaC::constant>(e)) {
    const double v = to_real(GiNaC::ex_to<GiNaC::numeric>(e.evalf()), e);
    result = {constant(std::fabs(v)), v < 0};
  } else if (GiNaC::is_exactly_a<GiNaC::add>(e)) {
    Instruction s;
    s.op = OpCode::sum;
    for (size_t k = 0; k < e.nops(); ++k) {
      const auto [term, negative] = lower_signed(e.op(k));
      s.args.push_back(term);
      s.negated.push_back(negative);
    }
    // The sign of the sum is that of its term with the smallest key: a − b and b − a become
    // the same instruction, one of them negated.
    size_t lead = 0;
    for (size_t k = 1; k < s.args.size(); ++k)
      if ((*this)[s.args[k]].key < (*this)[s.args[lead]].key) lead = k;
    const bool flip = s.negated[lead];
    if (flip)
      for (size_t k = 0; k < s.negated.size(); ++k) s.negated[k] = !s.negated[k];
    result = {make(std::move(s)), flip};
  } else if (GiNaC::is_exactly_a<GiNaC::mul>(e) || GiNaC::is_exactly_a<GiNaC::power>(e)) {
    result = lower_product(e);
  } else if (GiNaC::is_a<GiNaC::function>(e)) {
    result = {lower_function(e), false};
  } else {
    throw MathError("cannot generate code for " + describe(e));
  }
  by_expression_.emplace(e, result);
  return result;
}

std::pair<int, bool> ExpressionDag::lower_product(const GiNaC::ex& e) {
  std::vector<GiNaC::ex> factors;
  if (GiNaC::is_exactly_a<GiNaC::mul>(e))
    for (size_t k = 0; k < e.nops(); ++k) factors.push_back(e.op(k));
  else factors.push_back(e);

  bool negative = false;
  std::vector<int> numerator, denominator;
  for (const GiNaC::ex& f : factors) {
    if (GiNaC::is_exactly_a<GiNaC::numeric>(f)) {
      const double c = to_real(GiNaC::ex_to<GiNaC::numeric>(f), e);
      if (c < 0) negative = !negative;
      if (std::fabs(c) != 1.0) numerator.push_back(constant(std::fabs(c)));
      continue;
    }
    if (!GiNaC::is_exactly_a<GiNaC::power>(f)) {
      const auto [factor, sign] = lower_signed(f);
      if (sign) negative = !negative;
      numerator.push_back(factor);
      continue;
    }
    const GiNaC::ex base = f.op(0), exponent = f.op(1);
    if (!GiNaC::is_exactly_a<GiNaC::numeric>(exponent) || !GiNaC::ex_to<GiNaC::numeric>(exponent).is_rational()) {
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
      // (−b)^k = ±b^k.
      const int k = GiNaC::abs(num).to_int();
      const auto [b, sign] = lower_signed(base);
      if (sign && k % 2 == 1) negative = !negative;
      side.push_back(make_power(b, k));
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
  if (denominator.empty()) return {top, negative};
  Instruction d;
  d.op = OpCode::quotient;
  d.args = {top, make_product(std::move(denominator))};
  return {make(std::move(d)), negative};
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

std::vector<int> ExpressionDag::canonical_order(const std::vector<int>& outputs) const {
  std::vector<char> state(instructions_.size(), 0);  // 0 new, 1 open, 2 done
  std::vector<int> order;
  for (int root : outputs) {
    std::vector<std::pair<int, size_t>> stack = {{root, 0}};
    while (!stack.empty()) {
      auto& [id, next] = stack.back();
      const auto at = static_cast<size_t>(id);
      if (state[at] == 2) {
        stack.pop_back();
        continue;
      }
      state[at] = 1;
      const auto& args = instructions_[at].args;
      if (next < args.size()) {
        const int child = args[next++];
        if (state[static_cast<size_t>(child)] == 0) stack.emplace_back(child, 0);
        continue;
      }
      state[at] = 2;
      order.push_back(id);
      stack.pop_back();
    }
  }
  return order;
}

namespace {

long long saturating_sum(long long a, long long b) {
  long long sum = 0;
  return __builtin_add_overflow(a, b, &sum) ? kSaturatedOperations : sum;
}

}  // namespace

long long OperationCount::total() const {
  return saturating_sum(saturating_sum(additions, multiplications), saturating_sum(divisions, calls));
}

OperationCount& OperationCount::operator+=(const OperationCount& o) {
  additions = saturating_sum(additions, o.additions);
  multiplications = saturating_sum(multiplications, o.multiplications);
  divisions = saturating_sum(divisions, o.divisions);
  calls = saturating_sum(calls, o.calls);
  return *this;
}

std::string operation_count_text(long long count) {
  return count >= kSaturatedOperations ? std::string("more than 9.2e18") : std::to_string(count);
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
      for (int u = 0; u < uses && c.total() < kSaturatedOperations; ++u) c += tree[static_cast<size_t>(a)];
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
