#include "nhc/expr/cpp_printer.hpp"

#include <cmath>
#include <functional>
#include <string>

#include "nhc/errors.hpp"
#include "nhc/base/number_text.hpp"

namespace nhc {

namespace {

// Precedence of a printed expression: what it may stand next to without parentheses.
constexpr int kSum = 1;
constexpr int kProduct = 2;
constexpr int kUnary = 3;
constexpr int kAtom = 4;

struct Printed {
  std::string text;
  int level = kAtom;
};

/// How many times the printed code reads each operand: a power multiplied out and a sign
/// test read their operand more than once, which then must be a temporary.
int reads_of_operand(const Instruction& in) {
  switch (in.op) {
    case OpCode::integer_power:
      return in.exponent;
    case OpCode::sign:
    case OpCode::step:
      return 2;
    default:
      return 1;
  }
}

class BlockPrinter {
 public:
  /// `names`: a temporary's name per instruction ("" when inlined), or null when every
  /// instruction is inlined.
  BlockPrinter(const ExpressionDag& dag, const std::vector<std::string>* names) : dag_(dag), names_(names) {}

  Printed print(int id) const {
    if (names_) {
      const std::string& name = (*names_)[static_cast<size_t>(id)];
      if (!name.empty()) return {name, kAtom};
    }
    return print_definition(id);
  }

  Printed print_definition(int id) const {
    const Instruction& in = dag_[id];
    switch (in.op) {
      case OpCode::constant: {
        std::string text = cpp_double_literal(in.value);
        return {text, text[0] == '-' ? kUnary : kAtom};
      }
      case OpCode::input:
        return {in.name, kAtom};
      case OpCode::sum: {
        std::string text;
        for (size_t k = 0; k < in.args.size(); ++k) {
          if (k == 0) {
            text = operand(in.args[k], kSum);
            // Negation is exact, so −a·b may be read (−a)·b.
            if (in.negated[k]) text = "-" + operand(in.args[k], kProduct);
          } else {
            text += in.negated[k] ? " - " : " + ";
            text += operand(in.args[k], kProduct);
          }
        }
        return {text, kSum};
      }
      case OpCode::product: {
        std::string text;
        for (size_t k = 0; k < in.args.size(); ++k) {
          if (k > 0) text += " * ";
          text += operand(in.args[k], k == 0 ? kProduct : kAtom);
        }
        return {text, kProduct};
      }
      case OpCode::quotient:
        return {operand(in.args[0], kProduct) + " / " + operand(in.args[1], kAtom), kProduct};
      case OpCode::negate:
        return {"-" + operand(in.args[0], kAtom), kUnary};
      case OpCode::square_root:
        return {"std::sqrt(" + print(in.args[0]).text + ")", kAtom};
      case OpCode::integer_power: {
        const std::string base = operand(in.args[0], kAtom);
        std::string text = base;
        for (int k = 1; k < in.exponent; ++k) text += " * " + base;
        return {text, kProduct};
      }
      case OpCode::call: {
        std::string text = in.name + "(";
        for (size_t k = 0; k < in.args.size(); ++k) {
          if (k > 0) text += ", ";
          text += print(in.args[k]).text;
        }
        return {text + ")", kAtom};
      }
      case OpCode::sign: {
        const std::string a = operand(in.args[0], kAtom);
        return {"static_cast<double>((0.0 < " + a + ") - (" + a + " < 0.0))", kAtom};
      }
      case OpCode::step: {
        const std::string a = operand(in.args[0], kAtom);
        return {"(" + a + " < 0.0 ? 0.0 : (0.0 < " + a + " ? 1.0 : 0.5))", kAtom};
      }
    }
    return {};
  }

 private:
  std::string operand(int id, int needed) const {
    Printed p = print(id);
    if (p.level < needed) return "(" + p.text + ")";
    return p.text;
  }

  const ExpressionDag& dag_;
  const std::vector<std::string>* names_;  ///< temporary name per instruction, "" when inlined
};

}  // namespace

std::string cpp_double_literal(double v) {
  if (!std::isfinite(v)) throw MathError("cannot generate code for a non-finite constant");
  if (v == 0.0) return std::signbit(v) ? "-0.0" : "0.0";
  std::string text = base::number_text(v, 17);
  if (text.find_first_of(".eE") == std::string::npos) text += ".0";
  return text;
}

PrintedBlock print_cpp_block(const ExpressionDag& dag, const std::vector<Assignment>& assignments,
                             const std::string& indent) {
  std::vector<int> outputs;
  for (const auto& a : assignments) outputs.push_back(a.value);
  const std::vector<int> order = dag.canonical_order(outputs);

  std::vector<int> uses(static_cast<size_t>(dag.size()), 0);
  for (int id : order)
    for (int a : dag[id].args) uses[static_cast<size_t>(a)] += reads_of_operand(dag[id]);
  for (int o : outputs) ++uses[static_cast<size_t>(o)];

  PrintedBlock block;
  std::vector<std::string> names(static_cast<size_t>(dag.size()));
  BlockPrinter printer(dag, &names);
  std::string code;
  for (int id : order) {
    const Instruction& in = dag[id];
    if (in.op == OpCode::input) {
      block.used_inputs.insert(in.name.substr(0, in.name.find('[')));
      continue;
    }
    if (in.op == OpCode::constant || uses[static_cast<size_t>(id)] < 2) continue;
    const std::string name = "w" + std::to_string(block.temporaries++);
    code += indent + "const double " + name + " = " + printer.print_definition(id).text + ";\n";
    names[static_cast<size_t>(id)] = name;
  }
  for (const auto& a : assignments) {
    code += indent + a.target + " = " + printer.print(a.value).text + ";";
    if (!a.comment.empty()) code += "  // " + a.comment;
    code += "\n";
  }
  block.code = std::move(code);
  return block;
}

std::string print_cpp_expression(const ExpressionDag& dag, int id) {
  // No table of names: one per instruction of the whole DAG would make printing each of many
  // small expressions of one large DAG (a scene's L and its constraints) quadratic.
  return BlockPrinter(dag, nullptr).print_definition(id).text;
}

}  // namespace nhc
