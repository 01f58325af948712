#pragma once
/// \file evaluation_program.hpp
/// \brief The instructions of an ExpressionDag that some outputs reach, lowered once into a flat
/// register program and evaluated in doubles: the arithmetic of the generated code (cpp_printer),
/// operand for operand in the same order, without a compiler. The interpreted model
/// (nhc/jit/interpreted_model.hpp) runs every function of a header through it; the analysis's
/// numbers (NumericProgram) too. docs/interpreter.md says how it is laid out and what it costs.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
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

  /// The lowered program as bytes (the interpreted model's entry in the scene cache,
  /// nhc/jit/interpreted_model.hpp): the same program whatever reads it back, with no DAG to lower.
  std::string to_bytes() const;
  /// The program `bytes` holds (to_bytes()); nullopt when they are not one whose operations read
  /// and write registers it has, operands and functions it has, arguments below `arguments` and
  /// outputs below `outputs` (what run() may be given): malformed bytes are refused, not run.
  static std::optional<EvaluationProgram> from_bytes(std::string_view bytes, int arguments, int outputs);

  int register_count() const noexcept { return register_count_; }
  std::size_t operation_count() const noexcept { return operations_.empty() ? 0 : operations_.size() - 1; }

 private:
  // One operation of the program. Binary sums and products (most of a CSE'd list) have codes of
  // their own, so that they run without the operand list's indirection and loop.
  enum class Code : std::uint8_t {
    load,              ///< r[target] = arguments[a][b]
    add,               ///< r[a] + r[b]
    subtract,          ///< r[a] - r[b]
    negated_add,       ///< -r[a] + r[b]
    negated_subtract,  ///< -r[a] - r[b]
    sum,               ///< the operands operands_[a, a + b), signs negated_
    multiply,          ///< r[a] * r[b]
    multiply3,         ///< r[a] * r[b] * r[c]
    product,           ///< the operands operands_[a, a + b)
    quotient,
    negate,
    square_root,
    square,  ///< r[a] * r[a]
    power,   ///< r[a] multiplied out b times
    call1,   ///< unary_[b](r[a])
    call2,   ///< binary_[b](r[a], r[c])
    sincos,  ///< r[target], r[b] = sin, cos of r[a]
    sign,
    step,
    store,  ///< outputs[target][b] = r[a]
    halt,   ///< the last operation
  };
  struct Operation {
    Code code = Code::load;
    int target = 0;
    int a = 0;
    int b = 0;
    int c = 0;
  };

  void allocate_registers(const std::vector<int>& pinned, const std::vector<int>& kept);

  std::vector<Operation> operations_;
  std::vector<int> operands_;
  std::vector<char> negated_;
  std::vector<double (*)(double)> unary_;
  std::vector<double (*)(double, double)> binary_;
  std::vector<std::pair<int, double>> constants_;  ///< (register, value)
  int register_count_ = 0;
};

/// The C library function a `call` instruction names ("std::sin" → std::sin), or nullptr.
double (*unary_function(const std::string& name))(double);
double (*binary_function(const std::string& name))(double, double);

}  // namespace nhc
