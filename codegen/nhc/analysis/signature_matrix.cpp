#include "nhc/analysis/signature_matrix.hpp"

namespace nhc {

int signature_entry(const GiNaC::ex& f, const JetSpace& jet, VariableKind kind, int index) {
  // Orders of the variable that occur syntactically, tried from the highest down.
  for (int k = jet.highest_order(f, kind, index); k >= 0; --k) {
    const GiNaC::ex partial = f.diff(jet.symbol({kind, index, k}));
    if (!partial.is_zero() && !partial.normal().is_zero()) return k;
  }
  return SignatureMatrix::kAbsent;
}

SignatureMatrix signature_matrix(const DaeSystem& system) {
  const int n = system.size();
  SignatureMatrix sigma(n, static_cast<int>(system.unknowns.size()));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < sigma.cols(); ++j) {
      const Unknown& u = system.unknowns[static_cast<std::size_t>(j)];
      sigma(i, j) = signature_entry(system.equations[static_cast<std::size_t>(i)], *system.jet,
                                    u.kind, u.index);
    }
  return sigma;
}

}  // namespace nhc
