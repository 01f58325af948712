#include "nhc/analysis/transversal.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace nhc {

namespace {

/// Minimum-cost perfect assignment of an n×n cost matrix (1-based arrays inside), rows to
/// columns, by successive shortest augmenting paths with potentials u, v: each row is added
/// in O(n^2), O(n^3) in all. Returns the column of each row.
std::vector<int> min_cost_assignment(const std::vector<std::vector<long long>>& cost) {
  const int n = static_cast<int>(cost.size());
  const long long inf = std::numeric_limits<long long>::max() / 4;
  std::vector<long long> u(static_cast<std::size_t>(n + 1), 0), v(static_cast<std::size_t>(n + 1), 0);
  std::vector<int> row_of_col(static_cast<std::size_t>(n + 1), 0);  // p[j]: row matched to column j
  std::vector<int> way(static_cast<std::size_t>(n + 1), 0);
  auto at = [](auto& vec, int k) -> auto& { return vec[static_cast<std::size_t>(k)]; };
  for (int i = 1; i <= n; ++i) {
    at(row_of_col, 0) = i;
    int j0 = 0;
    std::vector<long long> minv(static_cast<std::size_t>(n + 1), inf);
    std::vector<char> used(static_cast<std::size_t>(n + 1), 0);
    do {
      at(used, j0) = 1;
      const int i0 = at(row_of_col, j0);
      long long delta = inf;
      int j1 = 0;
      for (int j = 1; j <= n; ++j) {
        if (at(used, j)) continue;
        const long long reduced =
            cost[static_cast<std::size_t>(i0 - 1)][static_cast<std::size_t>(j - 1)] - at(u, i0) - at(v, j);
        if (reduced < at(minv, j)) {
          at(minv, j) = reduced;
          at(way, j) = j0;
        }
        if (at(minv, j) < delta) {
          delta = at(minv, j);
          j1 = j;
        }
      }
      for (int j = 0; j <= n; ++j) {
        if (at(used, j)) {
          at(u, at(row_of_col, j)) += delta;
          at(v, j) -= delta;
        } else {
          at(minv, j) -= delta;
        }
      }
      j0 = j1;
    } while (at(row_of_col, j0) != 0);
    do {  // augment along the alternating path
      const int j1 = at(way, j0);
      at(row_of_col, j0) = at(row_of_col, j1);
      j0 = j1;
    } while (j0 != 0);
  }
  std::vector<int> col_of_row(static_cast<std::size_t>(n), -1);
  for (int j = 1; j <= n; ++j) col_of_row[static_cast<std::size_t>(at(row_of_col, j) - 1)] = j - 1;
  return col_of_row;
}

}  // namespace

std::optional<Transversal> highest_value_transversal(const SignatureMatrix& sigma) {
  const int n = sigma.rows();
  if (sigma.cols() != n) throw std::invalid_argument("signature matrix is not square");
  if (n == 0) return Transversal{};
  int lo = std::numeric_limits<int>::max(), hi = std::numeric_limits<int>::min();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (sigma.present(i, j)) {
        lo = std::min(lo, sigma(i, j));
        hi = std::max(hi, sigma(i, j));
      }
  if (lo > hi) return std::nullopt;  // no finite entry at all
  // Cost hi − σ ∈ [0, R]; a −∞ entry costs more than any assignment of finite entries can,
  // so the optimum uses one only when no finite transversal exists.
  const long long range = static_cast<long long>(hi) - lo;
  const long long forbidden = static_cast<long long>(n) * (range + 1) + 1;
  std::vector<std::vector<long long>> cost(static_cast<std::size_t>(n),
                                           std::vector<long long>(static_cast<std::size_t>(n)));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      cost[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)] =
          sigma.present(i, j) ? hi - static_cast<long long>(sigma(i, j)) : forbidden;
  Transversal t;
  t.column_of_row = min_cost_assignment(cost);
  for (int i = 0; i < n; ++i) {
    const int j = t.column_of_row[static_cast<std::size_t>(i)];
    if (!sigma.present(i, j)) return std::nullopt;
    t.value += sigma(i, j);
  }
  return t;
}

StructuralDeficiency structural_deficiency(const SignatureMatrix& sigma) {
  const int rows = sigma.rows(), cols = sigma.cols();
  std::vector<int> col_match(static_cast<std::size_t>(cols), -1), row_match(static_cast<std::size_t>(rows), -1);
  // Maximum bipartite matching by augmenting paths (Kuhn); the sizes here are tiny.
  std::vector<char> seen;
  auto augment = [&](auto&& self, int i) -> bool {
    for (int j = 0; j < cols; ++j) {
      if (!sigma.present(i, j) || seen[static_cast<std::size_t>(j)]) continue;
      seen[static_cast<std::size_t>(j)] = 1;
      if (col_match[static_cast<std::size_t>(j)] < 0 ||
          self(self, col_match[static_cast<std::size_t>(j)])) {
        col_match[static_cast<std::size_t>(j)] = i;
        row_match[static_cast<std::size_t>(i)] = j;
        return true;
      }
    }
    return false;
  };
  StructuralDeficiency result;
  for (int i = 0; i < rows; ++i) {
    seen.assign(static_cast<std::size_t>(cols), 0);
    if (augment(augment, i)) ++result.matching_size;
  }
  if (result.matching_size == rows) return result;
  // Rows reachable from the unmatched rows by alternating paths, and the columns they touch:
  // every such column is matched to a reachable row, so |cols| < |rows| (Kőnig).
  std::vector<char> row_in(static_cast<std::size_t>(rows), 0), col_in(static_cast<std::size_t>(cols), 0);
  std::vector<int> stack;
  for (int i = 0; i < rows; ++i)
    if (row_match[static_cast<std::size_t>(i)] < 0) {
      row_in[static_cast<std::size_t>(i)] = 1;
      stack.push_back(i);
    }
  while (!stack.empty()) {
    const int i = stack.back();
    stack.pop_back();
    for (int j = 0; j < cols; ++j) {
      if (!sigma.present(i, j) || col_in[static_cast<std::size_t>(j)]) continue;
      col_in[static_cast<std::size_t>(j)] = 1;
      const int r = col_match[static_cast<std::size_t>(j)];
      if (r >= 0 && !row_in[static_cast<std::size_t>(r)]) {
        row_in[static_cast<std::size_t>(r)] = 1;
        stack.push_back(r);
      }
    }
  }
  for (int i = 0; i < rows; ++i)
    if (row_in[static_cast<std::size_t>(i)]) result.rows.push_back(i);
  for (int j = 0; j < cols; ++j) {
    if (col_in[static_cast<std::size_t>(j)]) result.cols.push_back(j);
    if (col_match[static_cast<std::size_t>(j)] < 0) result.unmatched_cols.push_back(j);
  }
  return result;
}

}  // namespace nhc
