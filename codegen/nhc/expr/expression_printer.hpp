#pragma once
/// \file expression_printer.hpp
/// \brief Printing expressions for people and tools: GiNaC's default syntax (jet symbols as
/// plain identifiers such as `x_d2`, `^` for powers; readable back by parse_expression) and LaTeX
/// (jet symbols as `\dot{x}`, `\lambda_1`).

#include <ginac/ginac.h>

#include <string>

namespace nhc {

/// GiNaC default syntax; parse_expression() reads it back. Terms and factors are sorted by
/// their text, so that equal expressions print the same in every run (GiNaC's own order can
/// change between runs).
std::string to_text(const GiNaC::ex& e);
/// LaTeX math (no surrounding $).
std::string to_latex(const GiNaC::ex& e);

}  // namespace nhc
