#pragma once
/// \file symbol_substitution.hpp
/// \brief Substituting a map whose keys are symbols (jet symbols → states, symbols → numbers),
/// through named intermediates.
///
/// GiNaC's ex::subs(exmap, options) first scans every key of the map to learn whether some key
/// is a product or a power (for the pattern matching of expairseq::subschildren). With a map of
/// all 7N jet symbols of an N-body system that scan made each substitution O(N) however small
/// the expression, and a pass over N equations O(N²). Telling GiNaC that no key is a
/// product (subs_options::pattern_is_not_product) skips the scan; each symbol of the expression
/// is then one map lookup.
///
/// An intermediate (intermediate.hpp) is a symbol to GiNaC's subs, so its expression would keep
/// the old symbols. Here each intermediate an expression uses is mapped once, in dependency
/// order, to its image: a number when its expression becomes one, else an intermediate of the
/// same name over the new symbols. One SymbolSubstitution keeps its images, so every expression
/// it rewrites shares them (one instruction each in the generated code).

#include <ginac/ginac.h>

namespace nhc {

class SymbolSubstitution {
 public:
  /// Every key must be a symbol (no products, powers or other patterns).
  explicit SymbolSubstitution(GiNaC::exmap symbols) : map_(std::move(symbols)) {}
  GiNaC::ex operator()(const GiNaC::ex& e) const;
  const GiNaC::exmap& symbols() const { return map_; }

 private:
  /// The symbols, then each intermediate met so far → its image (a cache: the mapping itself
  /// does not change, so operator() is const).
  mutable GiNaC::exmap map_;
};

/// e with every symbol that is a key of `symbols` replaced by its value, through intermediates.
/// Every key must be a symbol (no products, powers or other patterns): keys of any other kind
/// are not matched.
GiNaC::ex substitute_symbols(const GiNaC::ex& e, const GiNaC::exmap& symbols);

}  // namespace nhc
