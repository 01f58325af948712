#include "nhc/analysis/offsets.hpp"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>

namespace nhc {

Offsets pryce_offsets(const SignatureMatrix& sigma, const Transversal& transversal) {
  const int n = sigma.rows();
  Offsets o;
  o.c.assign(static_cast<std::size_t>(n), 0);
  o.d.assign(static_cast<std::size_t>(n), 0);
  // Each sweep that changes c raises some c_i by at least 1, and the c_i are bounded above
  // by the canonical offsets (Pryce 2001, Lemma 3.5); this cap only guards against misuse
  // with a transversal that is not of highest value.
  long long bound = 1;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (sigma.present(i, j)) bound += std::abs(static_cast<long long>(sigma(i, j))) + 1;
  bound *= n + 1;
  for (long long sweep = 0;; ++sweep) {
    if (sweep > bound)
      throw std::logic_error("Pryce offset iteration did not converge: transversal not of highest value");
    for (int j = 0; j < n; ++j) {
      int d = SignatureMatrix::kAbsent;
      for (int i = 0; i < n; ++i)
        if (sigma.present(i, j)) d = std::max(d, sigma(i, j) + o.c[static_cast<std::size_t>(i)]);
      o.d[static_cast<std::size_t>(j)] = d;
    }
    bool changed = false;
    for (int i = 0; i < n; ++i) {
      const int j = transversal.column_of_row[static_cast<std::size_t>(i)];
      const int c = o.d[static_cast<std::size_t>(j)] - sigma(i, j);
      if (c != o.c[static_cast<std::size_t>(i)]) {
        o.c[static_cast<std::size_t>(i)] = c;
        changed = true;
      }
    }
    if (!changed) return o;
  }
}

}  // namespace nhc
