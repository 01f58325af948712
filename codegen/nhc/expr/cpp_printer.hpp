#pragma once
/// \file cpp_printer.hpp
/// \brief Printing an ExpressionDag as C++ statements.
///
/// Every instruction used more than once becomes one `const double wK = …;` temporary, declared
/// before its first use; the others are printed inline with the fewest parentheses that keep
/// the evaluation order of the instruction list. Powers x^2…x^4 are printed as products,
/// half-integer powers through std::sqrt, constants with 17 significant digits so that they
/// round-trip exactly (CasADi `CodeGenerator::constant`).

#include <set>
#include <string>
#include <vector>

#include "nhc/expr/expression_dag.hpp"

namespace nhc {

/// A double literal that reads back as exactly v: `%.17g`, with `.0` added to integers
/// (`2.0`, `0.10000000000000001`, `-1.5e-20`). Throws MathError for inf or NaN.
std::string cpp_double_literal(double v);

/// `target = <value>;`, with an optional trailing comment (already sanitised by the caller).
struct Assignment {
  std::string target;
  int value = 0;
  std::string comment;
};

struct PrintedBlock {
  std::string code;                   ///< the statements, one per line, each line indented
  std::set<std::string> used_inputs;  ///< array or scalar names the code reads: "y", "p", "t"…
  int temporaries = 0;
};

/// The statements computing all assignments from the instructions they reach.
PrintedBlock print_cpp_block(const ExpressionDag& dag, const std::vector<Assignment>& assignments,
                             const std::string& indent);

/// One expression with everything inlined (tests, diagnostics).
std::string print_cpp_expression(const ExpressionDag& dag, int id);

}  // namespace nhc
