#include "nhc/analysis/transversal.hpp"

#include <algorithm>
#include <functional>
#include <limits>
#include <queue>
#include <stdexcept>
#include <utility>

namespace nhc {

namespace {

constexpr long long kInfinity = std::numeric_limits<long long>::max() / 4;

/// Minimum-cost perfect assignment of rows to columns over the finite entries only, cost
/// hi − σ_ij ≥ 0, by successive shortest augmenting paths (Dijkstra on reduced costs with row
/// potentials u and column potentials v; Kuhn 1955, Munkres 1957, Jonker & Volgenant 1987,
/// in the sparse form of Duff & Koster 2001). Each search stops at the first free column it
/// settles and touches only the rows and columns it reaches, so on a sparse σ the work follows
/// the number of entries the searches meet, not n². Returns false when some row has no
/// augmenting path: then no perfect matching of finite entries exists (Berge).
class SparseAssignment {
 public:
  SparseAssignment(const SignatureMatrix& sigma, int hi)
      : sigma_(sigma),
        hi_(hi),
        n_(sigma.rows()),
        u_(static_cast<std::size_t>(n_), 0),
        v_(static_cast<std::size_t>(n_), 0),
        row_of_col_(static_cast<std::size_t>(n_), -1),
        col_of_row_(static_cast<std::size_t>(n_), -1),
        dist_(static_cast<std::size_t>(n_), kInfinity),
        pred_(static_cast<std::size_t>(n_), -1),
        settled_(static_cast<std::size_t>(n_), 0) {
    // Row reduction: u_i = min_j cost_ij keeps u_i + v_j ≤ cost_ij and makes each row's
    // cheapest entries tight, so most searches end at once.
    for (int i = 0; i < n_; ++i) {
      long long m = kInfinity;
      for (const auto& e : sigma_.row(i)) m = std::min(m, cost(e));
      u_[static_cast<std::size_t>(i)] = m == kInfinity ? 0 : m;
    }
  }

  bool solve() {
    for (int i = 0; i < n_; ++i)
      if (!augment(i)) return false;
    return true;
  }
  const std::vector<int>& column_of_row() const { return col_of_row_; }

 private:
  long long cost(const SignatureMatrix::Entry& e) const { return static_cast<long long>(hi_) - e.value; }
  long long reduced(int i, const SignatureMatrix::Entry& e) const {
    return cost(e) - u_[static_cast<std::size_t>(i)] - v_[static_cast<std::size_t>(e.col)];
  }

  /// Shortest augmenting path from the free row `start`; updates potentials and matching.
  bool augment(int start) {
    using Item = std::pair<long long, int>;  // (distance, column), smallest first
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> heap;
    std::vector<int> touched, settled_cols, visited_rows{start};
    std::vector<long long> row_dist{0};
    auto relax = [&](int r, long long dr) {
      for (const auto& e : sigma_.row(r)) {
        const auto j = static_cast<std::size_t>(e.col);
        if (settled_[j]) continue;
        const long long nd = dr + reduced(r, e);
        if (nd < dist_[j]) {
          if (dist_[j] == kInfinity) touched.push_back(e.col);
          dist_[j] = nd;
          pred_[j] = r;
          heap.emplace(nd, e.col);
        }
      }
    };
    relax(start, 0);
    int free_col = -1;
    long long delta = 0;
    while (!heap.empty()) {
      const auto [d, j] = heap.top();
      heap.pop();
      const auto js = static_cast<std::size_t>(j);
      if (settled_[js] || d != dist_[js]) continue;  // stale heap item
      settled_[js] = 1;
      settled_cols.push_back(j);
      const int r = row_of_col_[js];
      if (r < 0) {
        free_col = j;
        delta = d;
        break;
      }
      visited_rows.push_back(r);
      row_dist.push_back(d);  // the matched entry (r, j) has reduced cost 0
      relax(r, d);
    }
    if (free_col >= 0) {
      // Potentials: u_r += δ − dist(r) on the rows reached, v_j −= δ − dist(j) on the settled
      // columns; all reduced costs stay ≥ 0 and those on the path and the matching become 0.
      for (std::size_t k = 0; k < visited_rows.size(); ++k)
        u_[static_cast<std::size_t>(visited_rows[k])] += delta - row_dist[k];
      for (int j : settled_cols) v_[static_cast<std::size_t>(j)] -= delta - dist_[static_cast<std::size_t>(j)];
      for (int j = free_col;;) {  // flip the alternating path back to `start`
        const int r = pred_[static_cast<std::size_t>(j)];
        const int next = col_of_row_[static_cast<std::size_t>(r)];
        row_of_col_[static_cast<std::size_t>(j)] = r;
        col_of_row_[static_cast<std::size_t>(r)] = j;
        if (r == start) break;
        j = next;
      }
    }
    for (int j : touched) {
      dist_[static_cast<std::size_t>(j)] = kInfinity;
      settled_[static_cast<std::size_t>(j)] = 0;
    }
    return free_col >= 0;
  }

  const SignatureMatrix& sigma_;
  int hi_;
  int n_;
  std::vector<long long> u_, v_;
  std::vector<int> row_of_col_, col_of_row_;
  std::vector<long long> dist_;  ///< per column, kInfinity outside the current search
  std::vector<int> pred_;        ///< per column: the row the shortest path reaches it from
  std::vector<char> settled_;
};

}  // namespace

std::optional<Transversal> highest_value_transversal(const SignatureMatrix& sigma) {
  const int n = sigma.rows();
  if (sigma.cols() != n) throw std::invalid_argument("signature matrix is not square");
  if (n == 0) return Transversal{};
  int hi = std::numeric_limits<int>::min();
  for (int i = 0; i < n; ++i)
    for (const auto& e : sigma.row(i)) hi = std::max(hi, e.value);
  if (hi == std::numeric_limits<int>::min()) return std::nullopt;  // no finite entry at all
  SparseAssignment assignment(sigma, hi);
  if (!assignment.solve()) return std::nullopt;
  Transversal t;
  t.column_of_row = assignment.column_of_row();
  for (int i = 0; i < n; ++i) t.value += sigma(i, t.column_of_row[static_cast<std::size_t>(i)]);
  return t;
}

StructuralDeficiency structural_deficiency(const SignatureMatrix& sigma) {
  const int rows = sigma.rows(), cols = sigma.cols();
  std::vector<int> col_match(static_cast<std::size_t>(cols), -1), row_match(static_cast<std::size_t>(rows), -1);
  // Maximum bipartite matching by augmenting paths (Kuhn) over the finite entries.
  std::vector<int> seen(static_cast<std::size_t>(cols), -1);
  int stamp = -1;  // row whose search saw column j last
  auto augment = [&](auto&& self, int i) -> bool {
    for (const auto& e : sigma.row(i)) {
      const int j = e.col;
      if (seen[static_cast<std::size_t>(j)] == stamp) continue;
      seen[static_cast<std::size_t>(j)] = stamp;
      if (col_match[static_cast<std::size_t>(j)] < 0 || self(self, col_match[static_cast<std::size_t>(j)])) {
        col_match[static_cast<std::size_t>(j)] = i;
        row_match[static_cast<std::size_t>(i)] = j;
        return true;
      }
    }
    return false;
  };
  StructuralDeficiency result;
  for (int i = 0; i < rows; ++i) {
    stamp = i;
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
    for (const auto& e : sigma.row(i)) {
      const int j = e.col;
      if (col_in[static_cast<std::size_t>(j)]) continue;
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
