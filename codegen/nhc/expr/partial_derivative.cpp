#include "nhc/expr/partial_derivative.hpp"

#include "nhc/long_work.hpp"

namespace nhc {

GiNaC::ex partial_derivative(const GiNaC::ex& e, const GiNaC::symbol& s) {
  check_for_stop();
  if (GiNaC::is_exactly_a<GiNaC::add>(e)) {
    // D Σ c_k t_k = Σ c_k D t_k over the terms that depend on s.
    GiNaC::exvector terms;
    for (std::size_t k = 0; k < e.nops(); ++k) {
      GiNaC::ex d = partial_derivative(e.op(k), s);
      if (!d.is_zero()) terms.push_back(std::move(d));
    }
    if (terms.empty()) return 0;
    if (terms.size() == 1) return terms.front();
    return GiNaC::dynallocate<GiNaC::add>(terms);
  }
  if (GiNaC::is_exactly_a<GiNaC::mul>(e)) {
    // D Π f_k = Σ_k (Π_{j≠k} f_j)·D f_k over the factors that depend on s.
    const std::size_t n = e.nops();
    GiNaC::exvector terms;
    for (std::size_t k = 0; k < n; ++k) {
      GiNaC::ex d = partial_derivative(e.op(k), s);
      if (d.is_zero()) continue;
      GiNaC::exvector factors;
      factors.reserve(n);
      for (std::size_t j = 0; j < n; ++j) factors.push_back(j == k ? d : e.op(j));
      terms.push_back(GiNaC::dynallocate<GiNaC::mul>(factors));
    }
    if (terms.empty()) return 0;
    if (terms.size() == 1) return terms.front();
    return GiNaC::dynallocate<GiNaC::add>(terms);
  }
  if (GiNaC::is_exactly_a<GiNaC::power>(e) && GiNaC::is_exactly_a<GiNaC::numeric>(e.op(1))) {
    // D b^r = r·b^(r−1)·D b for a number r.
    const GiNaC::ex d = partial_derivative(e.op(0), s);
    if (d.is_zero()) return 0;
    return GiNaC::dynallocate<GiNaC::mul>(GiNaC::exvector{GiNaC::pow(e.op(0), e.op(1) - 1), d, e.op(1)});
  }
  if (GiNaC::is_exactly_a<GiNaC::numeric>(e)) return 0;
  return e.diff(s);
}

}  // namespace nhc
