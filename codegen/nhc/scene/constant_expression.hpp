#pragma once
/// \file constant_expression.hpp
/// \brief Numbers written as constant expressions in a scene: `alpha =
/// "pi/8"`, `x = [0.0, "v*cos(pi/6)"]`. Numbers, `pi`, `e`, the given names (the scene's
/// parameters, for [initial] and [simulate]), + − * / ^ (right-associative, above unary minus),
/// parentheses and sin cos tan asin acos atan sinh cosh tanh exp log sqrt abs, in double precision.

#include <map>
#include <string>

namespace nhc {

/// The value of `text`. Throws std::invalid_argument with the reason (an unknown name, a syntax
/// error at a column, a result that is not finite).
double evaluate_constant_expression(const std::string& text, const std::map<std::string, double>& names = {});

}  // namespace nhc
