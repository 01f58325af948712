#pragma once
/// \file elementary_derivatives.hpp
/// \brief Differentiation of GiNaC's elementary functions without an exception per call.
///
/// GiNaC's function::derivative first tries the function's explicit derivative and, where none is
/// registered (sin, cos, exp, … in GiNaC 1.8), catches the logic_error that attempt throws before
/// applying the chain rule. One throw per differentiated function costs about as much as the rest
/// of the differentiation: a third of `nhc generate` on the Whipple bicycle. Registering the chain
/// rule as the explicit derivative of each function the scene language offers gives the same
/// expressions (the same partial derivative times the argument's, in the same order) without it.

namespace nhc {

/// Registers the explicit derivatives, once per process (thread-safe, idempotent). Called where
/// functions enter nhc (the expression parser); expressions built elsewhere still differentiate
/// correctly, only by GiNaC's slower path.
void register_elementary_derivatives();

}  // namespace nhc
