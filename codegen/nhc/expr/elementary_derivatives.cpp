#include "nhc/expr/elementary_derivatives.hpp"

#include <ginac/ginac.h>

#include <mutex>

#include "nhc/expr/partial_derivative.hpp"

namespace nhc {

namespace {

using GiNaC::ex;
using GiNaC::power;
using GiNaC::symbol;

/// The chain rule f'(x)·x', written with the partial derivative GiNaC's own pderivative gives for
/// f (inifcns_trans.cpp), and 0 without evaluating f' when x does not depend on s (as GiNaC does).
template <class Partial>
ex chain(const ex& x, const symbol& s, Partial partial) {
  const ex dx = partial_derivative(x, s);
  if (dx.is_zero()) return 0;
  return partial(x) * dx;
}

ex sin_d(const ex& x, const symbol& s) {
  return chain(x, s, [](const ex& a) { return GiNaC::cos(a); });
}
ex cos_d(const ex& x, const symbol& s) {
  return chain(x, s, [](const ex& a) { return -GiNaC::sin(a); });
}
ex tan_d(const ex& x, const symbol& s) {
  return chain(x, s, [](const ex& a) { return 1 + power(GiNaC::tan(a), 2); });
}
ex exp_d(const ex& x, const symbol& s) {
  return chain(x, s, [](const ex& a) { return GiNaC::exp(a); });
}
ex log_d(const ex& x, const symbol& s) {
  return chain(x, s, [](const ex& a) { return power(a, -1); });
}
ex sinh_d(const ex& x, const symbol& s) {
  return chain(x, s, [](const ex& a) { return GiNaC::cosh(a); });
}
ex cosh_d(const ex& x, const symbol& s) {
  return chain(x, s, [](const ex& a) { return GiNaC::sinh(a); });
}
ex tanh_d(const ex& x, const symbol& s) {
  return chain(x, s, [](const ex& a) { return 1 - power(GiNaC::tanh(a), 2); });
}
ex asin_d(const ex& x, const symbol& s) {
  return chain(x, s, [](const ex& a) { return power(1 - power(a, 2), GiNaC::numeric(-1, 2)); });
}
ex acos_d(const ex& x, const symbol& s) {
  return chain(x, s, [](const ex& a) { return -power(1 - power(a, 2), GiNaC::numeric(-1, 2)); });
}
ex atan_d(const ex& x, const symbol& s) {
  return chain(x, s, [](const ex& a) { return power(1 + power(a, 2), -1); });
}
ex asinh_d(const ex& x, const symbol& s) {
  return chain(x, s, [](const ex& a) { return power(1 + power(a, 2), GiNaC::numeric(-1, 2)); });
}
ex acosh_d(const ex& x, const symbol& s) {
  return chain(x, s,
               [](const ex& a) { return power(a + -1, GiNaC::numeric(-1, 2)) * power(a + 1, GiNaC::numeric(-1, 2)); });
}
ex atanh_d(const ex& x, const symbol& s) {
  return chain(x, s, [](const ex& a) { return power(1 - power(a, 2), -1); });
}
/// atan2(y, x): ∂/∂y = x/(x² + y²), ∂/∂x = −y/(x² + y²), summed over the arguments in order.
ex atan2_d(const ex& y, const ex& x, const symbol& s) {
  ex result;
  if (const ex dy = partial_derivative(y, s); !dy.is_zero()) result += x / (power(x, 2) + power(y, 2)) * dy;
  if (const ex dx = partial_derivative(x, s); !dx.is_zero()) result += -y / (power(x, 2) + power(y, 2)) * dx;
  return result;
}

/// GiNaC keeps its function table protected in class function; a derived class may reach it.
struct FunctionTable : GiNaC::function {
  using GiNaC::function::registered_functions;
};

}  // namespace

void register_elementary_derivatives() {
  static std::once_flag once;
  std::call_once(once, [] {
    auto& table = FunctionTable::registered_functions();
    table[GiNaC::sin_SERIAL::serial].expl_derivative_func(sin_d);
    table[GiNaC::cos_SERIAL::serial].expl_derivative_func(cos_d);
    table[GiNaC::tan_SERIAL::serial].expl_derivative_func(tan_d);
    table[GiNaC::exp_SERIAL::serial].expl_derivative_func(exp_d);
    table[GiNaC::log_SERIAL::serial].expl_derivative_func(log_d);
    table[GiNaC::sinh_SERIAL::serial].expl_derivative_func(sinh_d);
    table[GiNaC::cosh_SERIAL::serial].expl_derivative_func(cosh_d);
    table[GiNaC::tanh_SERIAL::serial].expl_derivative_func(tanh_d);
    table[GiNaC::asin_SERIAL::serial].expl_derivative_func(asin_d);
    table[GiNaC::acos_SERIAL::serial].expl_derivative_func(acos_d);
    table[GiNaC::atan_SERIAL::serial].expl_derivative_func(atan_d);
    table[GiNaC::asinh_SERIAL::serial].expl_derivative_func(asinh_d);
    table[GiNaC::acosh_SERIAL::serial].expl_derivative_func(acosh_d);
    table[GiNaC::atanh_SERIAL::serial].expl_derivative_func(atanh_d);
    table[GiNaC::atan2_SERIAL::serial].expl_derivative_func(atan2_d);
  });
}

}  // namespace nhc
