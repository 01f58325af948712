#include "nhc/expr/symbol_substitution.hpp"

#include "nhc/expr/intermediate.hpp"

namespace nhc {

namespace {

GiNaC::ex substitute_plain(const GiNaC::ex& e, const GiNaC::exmap& map) {
  return e.subs(map, GiNaC::subs_options::no_pattern | GiNaC::subs_options::pattern_is_not_product);
}

}  // namespace

GiNaC::ex SymbolSubstitution::operator()(const GiNaC::ex& e) const {
  GiNaC::exmap& map = map_;
  for (const GiNaC::ex& d : intermediates_in_order({e})) {
    if (map.count(d)) continue;
    const Intermediate& i = GiNaC::ex_to<Intermediate>(d);
    const GiNaC::ex image = substitute_plain(i.expression(), map);
    if (GiNaC::is_a<GiNaC::numeric>(image) || image.is_equal(i.expression()))
      map.emplace(d, image.is_equal(i.expression()) ? d : image);
    else map.emplace(d, Intermediate(i.intermediate_name(), i.latex_name(), image, i.origin()));
  }
  return substitute_plain(e, map);
}

GiNaC::ex substitute_symbols(const GiNaC::ex& e, const GiNaC::exmap& symbols) {
  // Without intermediates, the map as given: copying it (7N symbols of an N-body system) for
  // every evaluation made the consistent point quadratic in N.
  if (direct_intermediates(e).empty()) return substitute_plain(e, symbols);
  return SymbolSubstitution(symbols)(e);
}

}  // namespace nhc
