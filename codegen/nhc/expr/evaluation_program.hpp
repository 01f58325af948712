#pragma once
/// \file evaluation_program.hpp
/// \brief The instructions of an ExpressionDag that some outputs reach, lowered once into a flat
/// register program and evaluated in doubles: the arithmetic of the generated code (cpp_printer),
/// operand for operand in the same order, without a compiler. The interpreted model
/// (nhc/jit/interpreted_model.hpp) runs every function of a header through it; the analysis's
/// numbers (NumericProgram) too. docs/interpreter.md says how it is laid out and what it costs.

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "nhc/expr/expression_dag.hpp"

namespace nhc {

class EvaluationProgram {
 public:
  /// Instruction `instruction`'s value goes to outputs[slot][index] (see run()).
  struct Output {
    int instruction = 0;
    int slot = 0;
    int index = 0;
  };
  /// Where an input instruction of the DAG reads its value: arguments[argument][index] of run().
  struct InputLocation {
    int argument = 0;
    int index = 0;
  };
  using InputLocator = std::function<InputLocation(const Instruction&)>;

  EvaluationProgram() = default;
  /// Lowers the instructions `outputs` reach; `locate` places each input instruction among the
  /// arguments (it throws for an input the caller does not provide).
  EvaluationProgram(const ExpressionDag& dag, const std::vector<Output>& outputs, const InputLocator& locate);

  /// Evaluates every output: arguments[k] points to argument k's values (a scalar by its
  /// address), outputs[slot][index] receives the results. `registers` is the caller's scratch,
  /// kept between calls (one per thread): sized, and the constants written, on first use.
  void run(const double* const* arguments, double* const* outputs, std::vector<double>& registers) const;

  int register_count() const noexcept { return register_count_; }
  std::size_t operation_count() const noexcept { return operations_.size(); }

 private:
  enum class Code : std::uint8_t { load, sum, product, quotient, negate, square_root, power, call1, call2, sincos, sign, step, store };
  struct Operation {
    Code code = Code::load;
    int target = 0;  ///< register written (store: the output slot)
    int a = 0;       ///< first operand register (load: argument; store: the register stored)
    int b = 0;       ///< second operand (load, store: the index; power: the exponent; sincos: the cosine's register)
    int first = 0;   ///< sum, product: the operands in operands_[first, first + count)
    int count = 0;
    double (*unary)(double) = nullptr;
    double (*binary)(double, double) = nullptr;
  };

  std::vector<Operation> operations_;
  std::vector<int> operands_;
  std::vector<char> negated_;
  std::vector<std::pair<int, double>> constants_;  ///< (register, value)
  int register_count_ = 0;
};

/// The C library function a `call` instruction names ("std::sin" → std::sin), or nullptr.
double (*unary_function(const std::string& name))(double);
double (*binary_function(const std::string& name))(double, double);

}  // namespace nhc
