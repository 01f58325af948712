#pragma once
/// \file partial_derivative.hpp
/// \brief ∂e/∂s by the sum, product and power rules, building only the terms that are not zero.
///
/// GiNaC's own `ex::diff` builds, for a product of n factors, n new products — one per factor,
/// that factor replaced by its derivative — and lets the sum drop the ones whose derivative is
/// zero; a power builds b^(r−1)·b' before looking at b'. When s occurs in few factors, as in the
/// partial derivatives of an intermediate with respect to each jet variable (a Jacobian column),
/// almost all of that work is thrown away: it was most of the Jacobian's cost for the Whipple
/// bicycle. Here a factor's derivative is computed first and a product is built only for the
/// factors whose derivative is not zero.
///
/// The result is the expression GiNaC's `diff` gives (the same terms, each put in GiNaC's
/// canonical form by the same constructors), so generated code is unchanged. Symbols, including
/// named intermediates (their memoized chain rule), functions and anything else are left to
/// `diff`.

#include <ginac/ginac.h>

namespace nhc {

/// ∂e/∂s, equal to e.diff(s).
GiNaC::ex partial_derivative(const GiNaC::ex& e, const GiNaC::symbol& s);

}  // namespace nhc
