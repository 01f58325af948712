#pragma once
/// \file expression_parser.hpp
/// \brief Parser for scene expressions into GiNaC expressions on a JetSpace.
///
/// Grammar (precedence low → high; `^` is right-associative and binds tighter than unary minus):
///   expr    := term (('+' | '-') term)*
///   term    := unary (('*' | '/') unary)*
///   unary   := ('+' | '-') unary | power
///   power   := postfix ('^' unary)?
///   postfix := primary ('[' expr (',' expr)? ']')?
///   primary := number | name '\''* | function '(' expr (',' expr)* ')' | '(' expr ')'
///            | '[' expr (',' expr)* ']'                       a vector, or a matrix of row vectors
/// Values are scalars, vectors and matrices (value.hpp); `*` is also matrix·vector and
/// matrix·matrix; `/` and `^` take scalars. Vector functions: dot cross norm transpose, rotations
/// rotx roty rotz, angular velocities omega omega_body. A name may be a definition (the
/// scene's [definitions]), with primes for its total derivative (`c'`).
/// Numbers are read exactly (0.5 → 1/2, 1e-3 → 1/1000) so that derivations stay exact.
/// Names: `t`, parameters, coordinates with primes (`x''`) or in printed jet form (`x_d2`),
/// and, where allowed, multipliers `lambda1`… (also with primes or `_d<k>`).
/// Scalar functions: sin cos tan exp log sqrt abs sinh cosh tanh asin acos atan atan2.
/// Constants: `pi` and `e` (`e^y` is exp(y)), unless the scene names a coordinate, parameter,
/// input or definition so (its own name hides the constant); `Pi` too, because GiNaC prints π
/// that way (acos(-1) evaluates to it). A complex constant (sqrt(-4)) is an error.

#include <ginac/ginac.h>

#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "nhc/expr/jet_space.hpp"
#include "nhc/scene/value.hpp"

namespace nhc {

/// Highest derivative order a scene may write (`x''''''''`); keeps derivations finite.
inline constexpr int kMaxDerivativeOrder = 8;
/// Largest numeric exponent of a non-numeric base (x^64); larger powers of sums cannot be expanded.
inline constexpr int kMaxExponent = 64;
/// Largest exact number, in bits of its numerator and denominator (2^4096): also the bound for
/// literals, products and powers of numbers.
inline constexpr int kMaxPowerBits = 4096;
/// Deepest parenthesis / operator nesting accepted.
inline constexpr int kMaxExpressionDepth = 200;
/// Highest tower of powers with non-numeric exponents (x^x^x^x^y is 4): GiNaC's normal form,
/// which derivations use, takes time exponential in it.
inline constexpr int kMaxExponentTower = 4;
/// Most factors of one product: the Euler operator differentiates products factor by factor
/// (300 factors in x took 11 s to derive, 64 take about a second).
inline constexpr std::size_t kMaxFactors = 64;
/// Largest expression, in nodes of its tree with definitions substituted: bounds the work of
/// everything downstream by size, not by a count of terms that a chain of 1024 bodies exceeds.
inline constexpr std::size_t kMaxNodes = 2000000;
/// Function calls nested deeper than this (definitions substituted) are refused: every
/// symbolic step recurses through the nesting, and the equations of sin(sin(…)) nested k deep
/// hold k factors of depth up to k (a chain of 200 definitions d_k = sin(d_{k-1}) took 14 s to
/// derive). Mechanics nests a handful deep.
inline constexpr std::size_t kMaxFunctionNesting = 32;
/// Largest total of kMaxNodes-style counts over all expressions of one scene: definitions used
/// many times are counted at every use, and each count is work.
inline constexpr std::size_t kMaxSceneNodes = 20000000;
/// Longest expression text accepted, in bytes.
inline constexpr std::size_t kMaxExpressionLength = 100000;
// How far an expression may expand is the work budget's (nhc/expr/work_budget.hpp): a short text
// such as (x+y+z+x'+y'+z'+t)^64, with its 10^8 terms, is refused as it is parsed.

/// A parse failure at a 0-based character offset of the expression text.
class ExpressionSyntaxError : public std::runtime_error {
 public:
  ExpressionSyntaxError(std::size_t offset, const std::string& message)
      : std::runtime_error(message), offset_(offset) {}
  std::size_t offset() const noexcept { return offset_; }

 private:
  std::size_t offset_;
};

struct ExpressionRules {
  bool allow_coordinates = true;   ///< q and its derivatives
  bool allow_multipliers = false;  ///< lambda1… and derivatives
  bool allow_time = true;          ///< t
  bool allow_inputs = true;        ///< the [inputs] names (where coordinates are allowed)
  /// A feedback law for input k (scene [inputs] of coordinates), written in its place wherever the
  /// input's name appears; nullopt: the input stays a symbol the run fills in.
  std::function<std::optional<GiNaC::ex>(int input)> input_law;
  /// The size limits above (length, nesting, exponents, numbers, expansion) guard against
  /// hostile scene files. Text nhc printed itself (JSON output read back) may exceed them: a
  /// product of powers prints as y^81, an expansion as larger numbers. Off: only the nesting
  /// bound stays, twenty times higher.
  bool input_limits = true;
  /// The value of a definition by name, or nullopt when the name is not one (the scene
  /// loader resolves [definitions] through it, in any order: definition_table.hpp). An error
  /// inside the definition comes out as the InputError it throws, located in its own text.
  std::function<std::optional<Value>(const std::string& name)> definition;
  /// Where omega() checks a matrix that is not built from rotx/roty/rotz.
  RotationCheck rotation_check;
  /// Nodes left for the whole scene (kMaxSceneNodes), shared by its expressions; null: no budget.
  std::shared_ptr<std::size_t> node_budget;
};

/// Parse `text` to a scalar; throws ExpressionSyntaxError on any error (a vector or matrix is one).
GiNaC::ex parse_expression(const std::string& text, const JetSpace& jet, const ExpressionRules& rules = {});
/// Parse `text` to a value of any shape (a definition).
Value parse_value(const std::string& text, const JetSpace& jet, const ExpressionRules& rules = {});

/// Names of the scene language's functions (scalar and vector), which no scene name may take.
const std::vector<std::string>& function_names();

}  // namespace nhc
