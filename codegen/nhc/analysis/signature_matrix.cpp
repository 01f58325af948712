#include "nhc/analysis/signature_matrix.hpp"

#include <algorithm>
#include <set>
#include <stdexcept>

#include "nhc/expr/partial_derivative.hpp"
#include "nhc/expr/work_budget.hpp"

namespace nhc {

int SignatureMatrix::operator()(int i, int j) const {
  const std::vector<Entry>& r = row(i);
  const auto it = std::lower_bound(r.begin(), r.end(), j, [](const Entry& e, int c) { return e.col < c; });
  return it != r.end() && it->col == j ? it->value : kAbsent;
}

void SignatureMatrix::set(int i, int j, int value) {
  if (j < 0 || j >= cols_) throw std::out_of_range("signature matrix column out of range");
  std::vector<Entry>& r = rows_.at(static_cast<std::size_t>(i));
  const auto it = std::lower_bound(r.begin(), r.end(), j, [](const Entry& e, int c) { return e.col < c; });
  const bool found = it != r.end() && it->col == j;
  if (value == kAbsent) {
    if (found) r.erase(it);
  } else if (found) {
    it->value = value;
  } else {
    r.insert(it, Entry{j, value});
  }
}

int signature_entry(const GiNaC::ex& f, const JetSpace& jet, VariableKind kind, int index) {
  // Orders of the variable that occur syntactically, tried from the highest down.
  for (int k = jet.highest_order(f, kind, index); k >= 0; --k) {
    const GiNaC::ex partial = partial_derivative(f, jet.symbol({kind, index, k}));
    if (!partial.is_zero() && !work_budget::is_zero(partial)) return k;
  }
  return SignatureMatrix::kAbsent;
}

SignatureMatrix signature_matrix(const DaeSystem& system) {
  const int n = system.size();
  SignatureMatrix sigma(n, static_cast<int>(system.unknowns.size()));
  // One pass over each equation's own jet coordinates: only the unknowns that occur in f_i are
  // tried, so the work is linear in the total size of the equations, not in N^2.
  const std::map<std::pair<VariableKind, int>, int> column = unknown_columns(system);
  for (int i = 0; i < n; ++i) {
    const GiNaC::ex& f = system.equations[static_cast<std::size_t>(i)];
    std::set<int> occurring;
    for (const JetCoordinate& c : system.jet->jet_coordinates_in(f)) {
      const auto it = column.find({c.kind, c.index});
      if (it != column.end()) occurring.insert(it->second);
    }
    for (int j : occurring) {
      const Unknown& u = system.unknowns[static_cast<std::size_t>(j)];
      sigma.set(i, j, signature_entry(f, *system.jet, u.kind, u.index));
    }
  }
  return sigma;
}

std::map<std::pair<VariableKind, int>, int> unknown_columns(const DaeSystem& system) {
  std::map<std::pair<VariableKind, int>, int> column;
  for (std::size_t j = 0; j < system.unknowns.size(); ++j)
    column[{system.unknowns[j].kind, system.unknowns[j].index}] = static_cast<int>(j);
  return column;
}

}  // namespace nhc
