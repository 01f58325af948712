#include "nhc/expr/evaluation_program.hpp"

#include <cmath>
#include <map>
#include <unordered_map>

#include "nhc/errors.hpp"

namespace nhc {

double (*unary_function(const std::string& name))(double) {
  static const std::map<std::string, double (*)(double)> functions = {
      {"std::sin", std::sin},     {"std::cos", std::cos},     {"std::tan", std::tan},   {"std::exp", std::exp},
      {"std::log", std::log},     {"std::sinh", std::sinh},   {"std::cosh", std::cosh}, {"std::tanh", std::tanh},
      {"std::asin", std::asin},   {"std::acos", std::acos},   {"std::atan", std::atan}, {"std::asinh", std::asinh},
      {"std::acosh", std::acosh}, {"std::atanh", std::atanh}, {"std::fabs", std::fabs}, {"std::sqrt", std::sqrt}};
  const auto f = functions.find(name);
  return f == functions.end() ? nullptr : f->second;
}

double (*binary_function(const std::string& name))(double, double) {
  static const std::map<std::string, double (*)(double, double)> functions = {{"std::pow", std::pow},
                                                                             {"std::atan2", std::atan2}};
  const auto f = functions.find(name);
  return f == functions.end() ? nullptr : f->second;
}

EvaluationProgram::EvaluationProgram(const ExpressionDag& dag, const std::vector<Output>& outputs,
                                     const InputLocator& locate) {
  std::vector<int> roots;
  for (const Output& o : outputs) roots.push_back(o.instruction);
  // reachable() is increasing in index, which is topological: operands come first.
  const std::vector<int> reached = dag.reachable(roots);
  std::unordered_map<int, int> register_of;
  for (int id : reached) register_of[id] = register_count_++;
  // sin and cos of one argument: one sincos call, as the compiler makes of the printed code.
  std::unordered_map<int, int> sine_of, cosine_of;  // argument instruction → the call
  for (int id : reached) {
    const Instruction& in = dag[id];
    if (in.op != OpCode::call || in.args.size() != 1) continue;
    if (in.name == "std::sin") sine_of[in.args[0]] = id;
    if (in.name == "std::cos") cosine_of[in.args[0]] = id;
  }
  std::unordered_map<int, bool> paired;  // call instruction → computed with its partner
  for (int id : reached) {
    const Instruction& in = dag[id];
    const int target = register_of.at(id);
    auto reg = [&](std::size_t k) { return register_of.at(in.args[k]); };
    Operation op;
    op.target = target;
    if (in.op == OpCode::call && in.args.size() == 1 && (in.name == "std::sin" || in.name == "std::cos")) {
      if (paired.count(id)) continue;
      const auto& partners = in.name == "std::sin" ? cosine_of : sine_of;
      const auto partner = partners.find(in.args[0]);
      if (partner != partners.end()) {
        paired[partner->second] = true;
        op.code = Code::sincos;
        op.a = reg(0);
        op.target = in.name == "std::sin" ? target : register_of.at(partner->second);
        op.b = in.name == "std::sin" ? register_of.at(partner->second) : target;
        operations_.push_back(op);
        continue;
      }
    }
    switch (in.op) {
      case OpCode::constant:
        constants_.emplace_back(target, in.value);
        continue;
      case OpCode::input: {
        const InputLocation at = locate(in);
        op.code = Code::load;
        op.a = at.argument;
        op.b = at.index;
        break;
      }
      case OpCode::sum:
      case OpCode::product:
        op.code = in.op == OpCode::sum ? Code::sum : Code::product;
        op.first = static_cast<int>(operands_.size());
        op.count = static_cast<int>(in.args.size());
        for (std::size_t k = 0; k < in.args.size(); ++k) {
          operands_.push_back(reg(k));
          negated_.push_back(in.op == OpCode::sum && in.negated[k] ? 1 : 0);
        }
        break;
      case OpCode::quotient:
        op.code = Code::quotient;
        op.a = reg(0);
        op.b = reg(1);
        break;
      case OpCode::negate:
        op.code = Code::negate;
        op.a = reg(0);
        break;
      case OpCode::square_root:
        op.code = Code::square_root;
        op.a = reg(0);
        break;
      case OpCode::integer_power:
        op.code = Code::power;
        op.a = reg(0);
        op.b = in.exponent;
        break;
      case OpCode::call:
        if (in.args.size() == 1 && (op.unary = unary_function(in.name))) {
          op.code = Code::call1;
          op.a = reg(0);
        } else if (in.args.size() == 2 && (op.binary = binary_function(in.name))) {
          op.code = Code::call2;
          op.a = reg(0);
          op.b = reg(1);
        } else {
          throw MathError("no numeric evaluation for " + in.name + " with " + std::to_string(in.args.size()) +
                          " arguments");
        }
        break;
      case OpCode::sign:
      case OpCode::step:
        op.code = in.op == OpCode::sign ? Code::sign : Code::step;
        op.a = reg(0);
        break;
    }
    operations_.push_back(op);
  }
  for (const Output& o : outputs) {
    Operation store;
    store.code = Code::store;
    store.target = o.slot;
    store.a = register_of.at(o.instruction);
    store.b = o.index;
    operations_.push_back(store);
  }
}

void EvaluationProgram::run(const double* const* arguments, double* const* outputs,
                            std::vector<double>& registers) const {
  if (registers.size() != static_cast<std::size_t>(register_count_)) {
    registers.assign(static_cast<std::size_t>(register_count_), 0.0);
    for (const auto& [at, value] : constants_) registers[static_cast<std::size_t>(at)] = value;
  }
  double* r = registers.data();
  const int* operand = operands_.data();
  const char* minus = negated_.data();
  // Each case computes as the printed code does (cpp_printer.cpp), left to right, so that the
  // interpreted and the compiled model agree to the last bit where the compiler keeps IEEE order.
  for (const Operation& op : operations_) {
    switch (op.code) {
      case Code::load: r[op.target] = arguments[op.a][op.b]; break;
      case Code::sum: {
        const int* k = operand + op.first;
        const char* s = minus + op.first;
        double v = s[0] ? -r[k[0]] : r[k[0]];
        for (int j = 1; j < op.count; ++j) v = s[j] ? v - r[k[j]] : v + r[k[j]];
        r[op.target] = v;
        break;
      }
      case Code::product: {
        const int* k = operand + op.first;
        double v = r[k[0]];
        for (int j = 1; j < op.count; ++j) v *= r[k[j]];
        r[op.target] = v;
        break;
      }
      case Code::quotient: r[op.target] = r[op.a] / r[op.b]; break;
      case Code::negate: r[op.target] = -r[op.a]; break;
      case Code::square_root: r[op.target] = std::sqrt(r[op.a]); break;
      case Code::power: {
        const double base = r[op.a];
        double v = base;
        for (int j = 1; j < op.b; ++j) v *= base;
        r[op.target] = v;
        break;
      }
      case Code::call1: r[op.target] = op.unary(r[op.a]); break;
      case Code::call2: r[op.target] = op.binary(r[op.a], r[op.b]); break;
      case Code::sincos: sincos(r[op.a], &r[op.target], &r[op.b]); break;
      case Code::sign: r[op.target] = static_cast<double>((0.0 < r[op.a]) - (r[op.a] < 0.0)); break;
      case Code::step: r[op.target] = r[op.a] < 0.0 ? 0.0 : (0.0 < r[op.a] ? 1.0 : 0.5); break;
      case Code::store: outputs[op.target][op.b] = r[op.a]; break;
    }
  }
}

}  // namespace nhc
