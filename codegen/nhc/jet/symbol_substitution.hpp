#pragma once
/// \file symbol_substitution.hpp
/// \brief Substituting a map whose keys are symbols (jet symbols → states, symbols → numbers).
///
/// GiNaC's ex::subs(exmap, options) first scans every key of the map to learn whether some key
/// is a product or a power (for the pattern matching of expairseq::subschildren). With a map of
/// all 7N jet symbols of an N-body system that scan made each substitution O(N) however small
/// the expression, and a pass over N equations O(N²) (issue 17). Telling GiNaC that no key is a
/// product (subs_options::pattern_is_not_product) skips the scan; each symbol of the expression
/// is then one map lookup.

#include <ginac/ginac.h>

namespace nhc {

/// e with every symbol that is a key of `symbols` replaced by its value. Every key must be a
/// symbol (no products, powers or other patterns): keys of any other kind are not matched.
inline GiNaC::ex substitute_symbols(const GiNaC::ex& e, const GiNaC::exmap& symbols) {
  return e.subs(symbols, GiNaC::subs_options::no_pattern | GiNaC::subs_options::pattern_is_not_product);
}

}  // namespace nhc
