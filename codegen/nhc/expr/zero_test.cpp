#include "nhc/expr/zero_test.hpp"

#include <algorithm>
#include <cmath>
#include <exception>

#include "nhc/expr/intermediate.hpp"
#include "nhc/expr/symbol_substitution.hpp"
#include "nhc/expr/symbolic_policy.hpp"
#include "nhc/expr/traversal.hpp"

namespace nhc {

namespace {

/// A fixed sequence in [0.25, 1.25): the same sample points in every run.
double filler(unsigned& state) {
  state = state * 1103515245u + 12345u;
  return 0.25 + static_cast<double>((state >> 8) % 10000) / 10000.0;
}

/// The symbols of e, intermediates included as symbols.
std::set<GiNaC::ex, GiNaC::ex_is_less> own_symbols_of(const GiNaC::ex& e) {
  std::set<GiNaC::ex, GiNaC::ex_is_less> out;
  visit_distinct(e, [&](const GiNaC::ex& x) {
    if (GiNaC::is_a<GiNaC::symbol>(x)) out.insert(x);
    return true;
  });
  return out;
}

/// e at `values` as a double; NaN when it is not a finite real number there (a pole, a branch
/// cut, a symbol left).
double value_at(const GiNaC::ex& e, const GiNaC::exmap& values, IntermediateValues intermediates) {
  try {
    const GiNaC::ex value =
        (intermediates == IntermediateValues::through ? substitute_symbols(e, values)
                                                      : e.subs(values, GiNaC::subs_options::no_pattern))
            .evalf();
    if (!GiNaC::is_a<GiNaC::numeric>(value)) return NAN;
    const GiNaC::numeric& n = GiNaC::ex_to<GiNaC::numeric>(value);
    if (!n.is_real()) return NAN;
    const double v = n.to_double();
    return std::isfinite(v) ? v : NAN;
  } catch (const std::exception&) {
    return NAN;
  }
}

}  // namespace

GiNaC::exmap sample_point(const std::set<GiNaC::ex, GiNaC::ex_is_less>& symbols, unsigned k,
                          const GiNaC::exmap& given) {
  static constexpr unsigned kSeeds[] = {777u, 4242u, 12345u};
  static_assert(sizeof kSeeds / sizeof kSeeds[0] >= kZeroTestPoints, "a seed per sample point");
  GiNaC::exmap values = given;
  unsigned state = kSeeds[k % kZeroTestPoints];
  for (const GiNaC::ex& s : symbols)
    if (!values.count(s)) values[s] = filler(state);
  return values;
}

bool vanishes_at_sample_points(const GiNaC::ex& e, const GiNaC::exmap& point, IntermediateValues intermediates) {
  if (e.is_zero()) return true;
  const auto symbols = intermediates == IntermediateValues::through ? symbols_through(e) : own_symbols_of(e);
  const bool by_terms = intermediates == IntermediateValues::as_symbols && GiNaC::is_exactly_a<GiNaC::add>(e);
  for (unsigned k = 0; k < kZeroTestPoints; ++k) {
    const GiNaC::exmap values = sample_point(symbols, k, point);
    double value = 0, scale = 0;
    if (by_terms) {
      for (std::size_t t = 0; t < e.nops(); ++t) {
        const double term = value_at(e.op(t), values, intermediates);
        value += term;
        scale = std::max(scale, std::fabs(term));
      }
    } else {
      value = value_at(e, values, intermediates);
    }
    if (!(std::fabs(value) <= kZeroTolerance * std::max(scale, 1.0))) return false;  // NaN too
  }
  return true;
}

}  // namespace nhc
