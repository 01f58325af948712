#pragma once
/// \file expression_printer.hpp
/// \brief Printing expressions for people and tools: GiNaC's default syntax (jet symbols as
/// plain identifiers such as `x_d2`, `^` for powers; readable back by parse_expression) and LaTeX
/// (jet symbols as `\dot{x}`, `\lambda_1`).

#include <ginac/ginac.h>

#include <string>

namespace nhc {

/// Where a subexpression stands in the one it belongs to: a term of a sum (or a whole
/// expression, a function's argument, an exponent), a factor of a product, or the base of a
/// power. Every printer, and every step that prints an expression in pieces (rows broken between
/// terms and factors, terms gathered by a symbol), brackets a subexpression by needs_brackets().
enum class Position { term, factor, base };

/// The one rule of when e, standing at `position`, is printed in brackets: a sum as a factor or a
/// base; a product, a quotient or a power as a base; a product or a number that starts with a
/// minus sign as a factor or a base; a number that is not an integer as a base.
bool needs_brackets(const GiNaC::ex& e, Position position);

/// GiNaC default syntax; parse_expression() reads it back. Terms and factors are sorted by
/// their text, so that equal expressions print the same in every run (GiNaC's own order can
/// change between runs).
std::string to_text(const GiNaC::ex& e);
/// LaTeX math (no surrounding $).
std::string to_latex(const GiNaC::ex& e);
/// LaTeX math of e standing at `position`, in brackets where needs_brackets() says so.
std::string to_latex(const GiNaC::ex& e, Position position);

}  // namespace nhc
