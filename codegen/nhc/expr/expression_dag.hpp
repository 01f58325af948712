#pragma once
/// \file expression_dag.hpp
/// \brief Common-subexpression elimination over GiNaC's expression DAG: expressions are lowered
/// to one flat, topologically sorted list of instructions in which every distinct subexpression
/// occurs once (after CasADi's `SXFunction`, which lowers its graph the same way before printing).
///
/// Sharing comes from hash-consing at two levels: GiNaC subexpressions are looked up by their
/// hash and `is_equal` (so `(x'^2+y'^2)^(-1/2)` in R_x and in dR_x/dx' is lowered once), and the
/// instructions the lowering synthesises (a `sqrt(b)` shared by `b^(1/2)` and `b^(-3/2)`, a
/// negation, a product) are looked up by their opcode and operands. One ExpressionDag is meant to
/// hold everything a generated header computes (residual, Jacobian, hidden constraints, …), so a
/// subexpression is one instruction wherever it occurs.

#include <ginac/ginac.h>

#include <cstdint>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

namespace nhc {

enum class OpCode {
  constant,       ///< `value`
  input,          ///< a named input such as `y[3]`, `p[0]`, `t`, `cj` (`name`)
  sum,            ///< Σ ±args[k]; `negated[k]` marks the subtracted operands
  product,        ///< Π args[k]
  quotient,       ///< args[0] / args[1]
  negate,         ///< −args[0]
  square_root,    ///< std::sqrt(args[0])
  integer_power,  ///< args[0]^exponent, exponent ≥ 2
  call,           ///< `name`(args…), e.g. std::sin, std::pow, std::atan2
  sign,           ///< csgn(args[0]): −1, 0, 1
  step,           ///< Heaviside step(args[0]): 0, 1/2, 1
};

/// Deterministic 64-bit mixing of structural keys (splitmix64 finaliser), the same on every
/// platform and run: Instruction::key, and the keys of passes over the DAG.
std::uint64_t mix_keys(std::uint64_t seed, std::uint64_t value);

struct Instruction {
  OpCode op = OpCode::constant;
  std::vector<int> args;      ///< operand instruction indices, all smaller than this one's
  std::vector<bool> negated;  ///< sum only
  double value = 0.0;         ///< constant only
  int exponent = 0;           ///< integer_power only
  std::string name;           ///< input: printed form; call: C++ function name
  /// Structural hash from the fields above and the operands' keys; independent of instruction
  /// indices and of GiNaC's term order (which follows object addresses and so changes from
  /// run to run). Operands of sums and products are sorted by it, and the printer walks the
  /// DAG in operand order, so the printed code is the same in every run.
  std::uint64_t key = 0;

  /// Compares content (not `key`), for hash-consing.
  bool operator<(const Instruction& o) const;
};

/// The instruction list. Lowering never removes instructions; evaluate only what the outputs
/// reach (reachable()).
class ExpressionDag {
 public:
  /// `inputs` maps each symbol that may occur to its printed form ("y[3]", "t").
  explicit ExpressionDag(std::map<GiNaC::ex, std::string, GiNaC::ex_is_less> inputs);

  /// Lowers e and returns the index of the instruction computing it. Throws MathError for a
  /// symbol that is not an input, a non-real number or a function without a C++ counterpart.
  /// A named intermediate (nhc/expr/intermediate.hpp) is lowered through its expression, once,
  /// unless it is an input itself (printed by name: scene notation of the equations). Its
  /// expression must be over the inputs too: Index1System::in_states rewrites intermediates
  /// in states before they get here.
  int add(const GiNaC::ex& e);

  /// Appends an instruction whose operands are instructions of this DAG (or returns the equal
  /// one already there); sums and products get their canonical operand order. For passes that
  /// rewrite a DAG (common_arguments.hpp).
  int append(Instruction instruction) { return make(std::move(instruction)); }

  const std::vector<Instruction>& instructions() const { return instructions_; }
  const Instruction& operator[](int id) const { return instructions_[static_cast<size_t>(id)]; }
  int size() const { return static_cast<int>(instructions_.size()); }

  /// Instructions the outputs depend on, in increasing (topological) order.
  std::vector<int> reachable(const std::vector<int>& outputs) const;
  /// The same set in a canonical topological order: depth-first from the outputs in order,
  /// operands in order, each instruction after its operands.
  std::vector<int> canonical_order(const std::vector<int>& outputs) const;

 private:
  int lower(const GiNaC::ex& e);
  static const GiNaC::ex& intermediate_expression(const GiNaC::ex& d);
  /// Lowers e as ±(instruction): returns the instruction and whether the sign is negative.
  std::pair<int, bool> lower_signed(const GiNaC::ex& e);
  std::pair<int, bool> lower_product(const GiNaC::ex& e);
  /// −(instruction id) without a negation, by flipping the signs of a sum in it; −1 if none.
  int negated(int id);
  int lower_function(const GiNaC::ex& e);
  int constant(double value);
  int make(Instruction instruction);
  int make_product(std::vector<int> factors);
  int make_power(int base, int exponent);

  std::map<GiNaC::ex, std::string, GiNaC::ex_is_less> inputs_;
  std::vector<Instruction> instructions_;
  std::map<Instruction, int> by_instruction_;
  std::unordered_map<GiNaC::ex, std::pair<int, bool>, std::hash<GiNaC::ex>, GiNaC::ex_is_equal> by_expression_;
};

/// Floating-point operations, counted as the printed C++ performs them: an n-ary sum or product
/// is n − 1 operations, x^k (k ≤ 4) is k − 1 multiplications, a function call is one.
struct OperationCount {
  long long additions = 0;  ///< + and − (binary and unary)
  long long multiplications = 0;
  long long divisions = 0;
  long long calls = 0;  ///< sqrt, pow, sin, …
  /// The sum of the four; every count saturates at kSaturatedOperations instead of wrapping (a
  /// chain of definitions d_k = d_{k-1}² + x doubles the tree count at every step).
  long long total() const;
  OperationCount& operator+=(const OperationCount& o);
};

/// The value at which operation counts stop growing (LLONG_MAX, about 9.2e18).
inline constexpr long long kSaturatedOperations = 9223372036854775807LL;

/// A count in words: the number, or "more than 9.2e18" when it saturated.
std::string operation_count_text(long long count);

/// Cost of one instruction by itself.
OperationCount instruction_cost(const Instruction& instruction);
/// Without CSE: every output evaluated as a tree, shared subexpressions counted at every use.
OperationCount tree_operation_count(const ExpressionDag& dag, const std::vector<int>& outputs);
/// With CSE: every instruction the outputs reach counted once.
OperationCount dag_operation_count(const ExpressionDag& dag, const std::vector<int>& outputs);

}  // namespace nhc
