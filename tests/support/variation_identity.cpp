#include "variation_identity.hpp"

#include <stdexcept>

namespace nhc::testing {

namespace {

// Undetermined constraint functions of (t, q, q', …, q^(m)); GiNaC differentiates them
// formally (D[k](f)), which keeps f generic.
DECLARE_FUNCTION_3P(generic_f1)
DECLARE_FUNCTION_4P(generic_f2)
DECLARE_FUNCTION_5P(generic_f3)
REGISTER_FUNCTION(generic_f1, latex_name("f"))
REGISTER_FUNCTION(generic_f2, latex_name("f"))
REGISTER_FUNCTION(generic_f3, latex_name("f"))

}  // namespace

VariationIdentity::VariationIdentity(int m) : m_(m), jet_({"q", "eta"}, 0, {}) {
  const GiNaC::ex t = jet_.time();
  switch (m) {
    case 1:
      f_ = generic_f1(t, jet_.q(0, 0), jet_.q(0, 1));
      break;
    case 2:
      f_ = generic_f2(t, jet_.q(0, 0), jet_.q(0, 1), jet_.q(0, 2));
      break;
    case 3:
      f_ = generic_f3(t, jet_.q(0, 0), jet_.q(0, 1), jet_.q(0, 2), jet_.q(0, 3));
      break;
    default:
      throw std::invalid_argument("VariationIdentity: m must be 1, 2 or 3");
  }
  for (int k = 0; k <= m; ++k) varied_.emplace_back("delta_q_d" + std::to_string(k));
}

GiNaC::ex VariationIdentity::partial(int k) const { return f_.diff(GiNaC::ex_to<GiNaC::symbol>(jet_.q(0, k))); }

GiNaC::ex VariationIdentity::total_derivative(const GiNaC::ex& e, int times) const {
  return jet_.total_derivative(e, times);
}

GiNaC::ex VariationIdentity::variation_derivative(int j) const { return jet_.q(1, j); }

GiNaC::ex VariationIdentity::varied_derivative(int k) const { return varied_.at(static_cast<std::size_t>(k)); }

GiNaC::ex VariationIdentity::remainder() const {
  const GiNaC::ex dq = variation_derivative(0);
  GiNaC::ex delta_f = partial(0) * dq;
  for (int k = 1; k <= m_; ++k) delta_f += partial(k) * varied_derivative(k);
  GiNaC::ex lhs = 0;
  GiNaC::ex bracket = partial(0);
  for (int k = 1; k <= m_; ++k) {
    lhs += partial(k) * (varied_derivative(k) - variation_derivative(k));  // first sum
    lhs += total_derivative(partial(k) * dq, k);                           // second sum
    bracket -= total_derivative(partial(k), k);
  }
  lhs += -delta_f + bracket * dq;
  return lhs.expand();
}

GiNaC::ex VariationIdentity::leibniz_cross_terms() const {
  GiNaC::ex sum = 0;
  for (int k = 2; k <= m_; ++k)
    for (int j = 1; j < k; ++j)
      sum += GiNaC::binomial(GiNaC::numeric(k), GiNaC::numeric(j)) * total_derivative(partial(k), k - j) *
             variation_derivative(j);
  return sum.expand();
}

}  // namespace nhc::testing
