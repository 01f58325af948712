#include "nhc/jet/zero_test.hpp"

#include <cmath>
#include <exception>

#include "nhc/jet/intermediate.hpp"
#include "nhc/jet/symbol_substitution.hpp"

namespace nhc {

namespace {

/// A fixed sequence in [0.25, 1.25): the same sample points in every run.
double filler(unsigned& state) {
  state = state * 1103515245u + 12345u;
  return 0.25 + static_cast<double>((state >> 8) % 10000) / 10000.0;
}

}  // namespace

bool vanishes_at_sample_points(const GiNaC::ex& e, const GiNaC::exmap& point) {
  if (e.is_zero()) return true;
  // Two points: one would do almost surely; the second guards a value that happens to be small.
  for (unsigned seed : {777u, 4242u}) {
    GiNaC::exmap values = point;
    unsigned state = seed;
    for (const GiNaC::ex& s : symbols_through(e))
      if (!values.count(s)) values[s] = filler(state);
    try {
      const GiNaC::ex value = substitute_symbols(e, values).evalf();
      if (!GiNaC::is_a<GiNaC::numeric>(value)) return false;
      if (!(GiNaC::abs(GiNaC::ex_to<GiNaC::numeric>(value)).to_double() < 1e-9)) return false;
    } catch (const std::exception&) {
      return false;  // a pole at the sample point: not known to vanish
    }
  }
  return true;
}

}  // namespace nhc
