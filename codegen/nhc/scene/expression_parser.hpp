#pragma once
/// \file expression_parser.hpp
/// \brief Parser for scene expressions into GiNaC expressions on a JetSpace.
///
/// Grammar (precedence low → high; `^` is right-associative and binds tighter than unary minus):
///   expr    := term (('+' | '-') term)*
///   term    := unary (('*' | '/') unary)*
///   unary   := ('+' | '-') unary | power
///   power   := primary ('^' unary)?
///   primary := number | name '\''* | function '(' expr (',' expr)* ')' | '(' expr ')'
/// Numbers are read exactly (0.5 → 1/2, 1e-3 → 1/1000) so that derivations stay exact.
/// Names: `t`, parameters, coordinates with primes (`x''`) or in printed jet form (`x_d2`),
/// and, where allowed, multipliers `lambda1`… (also with primes or `_d<k>`).
/// Functions: sin cos tan exp log sqrt abs sinh cosh tanh asin acos atan atan2.
/// The constant `Pi` is accepted because GiNaC prints π that way (acos(-1) evaluates to it);
/// a complex constant (sqrt(-4)) is an error.

#include <ginac/ginac.h>

#include <stdexcept>
#include <string>

#include "nhc/jet/jet_space.hpp"

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
/// Most factors of one product and terms of one sum: the Euler operator differentiates products
/// factor by factor (300 factors in x took 11 s to derive, 64 take about a second).
inline constexpr std::size_t kMaxFactors = 64;
inline constexpr std::size_t kMaxTerms = 1000;
/// Longest expression text accepted, in bytes.
inline constexpr std::size_t kMaxExpressionLength = 100000;
/// Largest number of terms an expression may expand to (bounded from its structure: (a+b+c)^k
/// has at most C(k+2, 2) terms); derivations expand, so a short text such as
/// (x+y+z+x'+y'+z'+t)^64 with its 10^8 terms would exhaust time and memory, and printing an
/// expansion of 10^5 terms took seconds.
inline constexpr double kMaxExpandedTerms = 1e4;

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
  /// The size limits above (length, nesting, exponents, numbers, expansion) guard against
  /// hostile scene files. Text nhc printed itself (JSON output read back) may exceed them: a
  /// product of powers prints as y^81, an expansion as larger numbers. Off: only the nesting
  /// bound stays, twenty times higher.
  bool input_limits = true;
};

/// Parse `text`; throws ExpressionSyntaxError on any error.
GiNaC::ex parse_expression(const std::string& text, const JetSpace& jet,
                           const ExpressionRules& rules = {});

}  // namespace nhc
