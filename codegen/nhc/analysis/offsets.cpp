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
    for (const auto& e : sigma.row(i)) bound += std::abs(static_cast<long long>(e.value)) + 1;
  bound *= n + 1;
  // Transversal entries σ_{i,T(i)}, looked up once.
  std::vector<int> on_transversal(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    on_transversal[static_cast<std::size_t>(i)] = sigma(i, transversal.column_of_row[static_cast<std::size_t>(i)]);
  // Each sweep passes once over the finite entries (row by row): O(entries) per sweep.
  for (long long sweep = 0;; ++sweep) {
    if (sweep > bound)
      throw std::logic_error("Pryce offset iteration did not converge: transversal not of highest value");
    std::fill(o.d.begin(), o.d.end(), SignatureMatrix::kAbsent);
    for (int i = 0; i < n; ++i)
      for (const auto& e : sigma.row(i)) {
        int& d = o.d[static_cast<std::size_t>(e.col)];
        d = std::max(d, e.value + o.c[static_cast<std::size_t>(i)]);
      }
    bool changed = false;
    for (int i = 0; i < n; ++i) {
      const int j = transversal.column_of_row[static_cast<std::size_t>(i)];
      const int c = o.d[static_cast<std::size_t>(j)] - on_transversal[static_cast<std::size_t>(i)];
      if (c != o.c[static_cast<std::size_t>(i)]) {
        o.c[static_cast<std::size_t>(i)] = c;
        changed = true;
      }
    }
    if (!changed) return o;
  }
}

}  // namespace nhc
