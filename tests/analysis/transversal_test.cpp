// The sparse Hungarian transversal and Pryce's offsets against brute force and the dense method, and the Σ-method on
// the textbook index-3 pendulum (Pryce 2001, §2 example).
#include <catch2/catch.hpp>

#include <algorithm>
#include <limits>
#include <numeric>
#include <random>

#include "analysis_test_support.hpp"
#include "nhc/analysis/offsets.hpp"
#include "nhc/analysis/structural_analysis.hpp"
#include "nhc/analysis/transversal.hpp"

using namespace nhc;

namespace {

constexpr int X = SignatureMatrix::kAbsent;

SignatureMatrix matrix(const std::vector<std::vector<int>>& rows) {
  SignatureMatrix s(static_cast<int>(rows.size()), static_cast<int>(rows.size()));
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t j = 0; j < rows.size(); ++j) s.set(static_cast<int>(i), static_cast<int>(j), rows[i][j]);
  return s;
}

/// Best Σ σ_{i,p(i)} over all permutations with finite entries, or nullopt.
std::optional<long long> brute_force_value(const SignatureMatrix& s) {
  std::vector<int> p(static_cast<std::size_t>(s.rows()));
  std::iota(p.begin(), p.end(), 0);
  std::optional<long long> best;
  do {
    long long v = 0;
    bool finite = true;
    for (int i = 0; i < s.rows() && finite; ++i) {
      finite = s.present(i, p[static_cast<std::size_t>(i)]);
      if (finite) v += s(i, p[static_cast<std::size_t>(i)]);
    }
    if (finite && (!best || v > *best)) best = v;
  } while (std::next_permutation(p.begin(), p.end()));
  return best;
}

SignatureMatrix random_matrix(std::mt19937& rng, int n, double absent_probability) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::uniform_int_distribution<int> order(0, 4);
  SignatureMatrix s(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) s.set(i, j, u(rng) < absent_probability ? X : order(rng));
  return s;
}

}  // namespace

TEST_CASE("Hungarian transversal has the brute-force highest value", "[sigma]") {
  std::mt19937 rng(20260101);
  int singular = 0, regular = 0;
  for (int trial = 0; trial < 600; ++trial) {
    const int n = 1 + trial % 7;
    const SignatureMatrix s = random_matrix(rng, n, trial % 3 == 0 ? 0.6 : 0.3);
    const auto expected = brute_force_value(s);
    const auto t = highest_value_transversal(s);
    REQUIRE(t.has_value() == expected.has_value());
    if (!t) {
      ++singular;
      // Kőnig witness: rows whose finite entries lie in fewer columns.
      const StructuralDeficiency def = structural_deficiency(s);
      REQUIRE(def.cols.size() < def.rows.size());
      REQUIRE(def.matching_size < n);
      for (int i : def.rows)
        for (int j = 0; j < n; ++j)
          if (s.present(i, j)) REQUIRE(std::count(def.cols.begin(), def.cols.end(), j) == 1);
      continue;
    }
    ++regular;
    REQUIRE(t->value == *expected);
    std::vector<int> cols = t->column_of_row;
    std::sort(cols.begin(), cols.end());
    for (int j = 0; j < n; ++j) REQUIRE(cols[static_cast<std::size_t>(j)] == j);  // a permutation
    long long sum = 0;
    for (int i = 0; i < n; ++i) {
      REQUIRE(s.present(i, t->column_of_row[static_cast<std::size_t>(i)]));
      sum += s(i, t->column_of_row[static_cast<std::size_t>(i)]);
    }
    REQUIRE(sum == t->value);
  }
  REQUIRE(singular > 20);
  REQUIRE(regular > 300);
}

TEST_CASE("Pryce offsets are valid and the smallest (brute force)", "[sigma]") {
  std::mt19937 rng(7);
  int checked = 0;
  for (int trial = 0; trial < 300 && checked < 120; ++trial) {
    const int n = 1 + trial % 4;
    const SignatureMatrix s = random_matrix(rng, n, 0.35);
    const auto t = highest_value_transversal(s);
    if (!t) continue;
    ++checked;
    const Offsets o = pryce_offsets(s, *t);
    long long sum = 0;
    for (int i = 0; i < n; ++i) {
      REQUIRE(o.c[static_cast<std::size_t>(i)] >= 0);
      const int j = t->column_of_row[static_cast<std::size_t>(i)];
      REQUIRE(o.d[static_cast<std::size_t>(j)] - o.c[static_cast<std::size_t>(i)] == s(i, j));
      for (int k = 0; k < n; ++k)
        if (s.present(i, k)) REQUIRE(o.d[static_cast<std::size_t>(k)] - o.c[static_cast<std::size_t>(i)] >= s(i, k));
      sum += o.d[static_cast<std::size_t>(i)] - o.c[static_cast<std::size_t>(i)];
    }
    REQUIRE(sum == t->value);  // Σd − Σc = value of a highest-value transversal (LP duality)
    // Every valid c in [0, 8]^n (with the smallest d it allows) dominates the canonical c.
    std::vector<int> c(static_cast<std::size_t>(n), 0);
    for (;;) {
      long long total = 0;
      for (int j = 0; j < n; ++j) {
        int d = X;
        for (int i = 0; i < n; ++i)
          if (s.present(i, j)) d = std::max(d, s(i, j) + c[static_cast<std::size_t>(i)]);
        total += d;
      }
      for (int i = 0; i < n; ++i) total -= c[static_cast<std::size_t>(i)];
      if (total == t->value)
        for (int i = 0; i < n; ++i) REQUIRE(o.c[static_cast<std::size_t>(i)] <= c[static_cast<std::size_t>(i)]);
      int k = 0;
      while (k < n && ++c[static_cast<std::size_t>(k)] > 8) c[static_cast<std::size_t>(k++)] = 0;
      if (k == n) break;
    }
  }
  REQUIRE(checked >= 100);
}

TEST_CASE("the pendulum is index 3 with 2 degrees of freedom", "[sigma]") {
  // x'' + x λ = 0, y'' + y λ − g = 0, x² + y² − L² = 0 (Pryce 2001, §2):
  // σ = [[2,−,0],[−,2,0],[0,0,−]]; c = (0,0,2), d = (2,2,0): the constraint is differentiated
  // twice; ν = max c + 1 (λ algebraic) = 3; dof = 4 − 2 = 2; hidden constraints C and D C.
  auto jet = std::make_shared<JetSpace>(std::vector<std::string>{"x", "y"}, 1, std::vector<std::string>{"g", "L"});
  DaeSystem sys;
  sys.jet = jet;
  sys.unknowns = {
      {VariableKind::coordinate, 0, "x"}, {VariableKind::coordinate, 1, "y"}, {VariableKind::multiplier, 0, "lambda1"}};
  const GiNaC::ex x = jet->q(0, 0), y = jet->q(1, 0), lam = jet->lambda(0, 0);
  sys.equations = {jet->q(0, 2) + x * lam, jet->q(1, 2) + y * lam - jet->parameter(0),
                   x * x + y * y - GiNaC::pow(jet->parameter(1), 2)};
  sys.equation_names = {"A", "B", "C"};
  const StructuralAnalysis a = analyze_structure(sys);
  REQUIRE_FALSE(a.structurally_singular);
  const std::vector<std::vector<int>> sigma = {{2, X, 0}, {X, 2, 0}, {0, 0, X}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) CHECK(a.sigma(i, j) == sigma[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)]);
  CHECK(a.offsets.c == std::vector<int>{0, 0, 2});
  CHECK(a.offsets.d == std::vector<int>{2, 2, 0});
  CHECK(a.index == 3);
  CHECK(a.dof == 2);
  REQUIRE(a.hidden_constraints.size() == 2);
  CHECK(a.hidden_constraints[0].name == "C");
  CHECK(a.hidden_constraints[1].name == "D C");
  // D C = 2 x x' + 2 y y' (hand).
  const GiNaC::ex dc = differentiated_equation(a, 2, 1);
  CHECK((dc - (2 * x * jet->q(0, 1) + 2 * y * jet->q(1, 1))).expand().is_zero());
}

TEST_CASE("structural deficiency names the offending equations", "[sigma]") {
  // Rows 0 and 1 only touch column 0.
  const SignatureMatrix s = matrix({{1, X, X}, {0, X, X}, {2, 1, 0}});
  REQUIRE_FALSE(highest_value_transversal(s));
  const StructuralDeficiency def = structural_deficiency(s);
  CHECK(def.rows == std::vector<int>{0, 1});
  CHECK(def.cols == std::vector<int>{0});
  CHECK(def.matching_size == 2);
}

namespace {

/// Independent reference: the dense O(n³) Hungarian method on the full n×n cost matrix
/// hi − σ_ij, with −∞ entries priced above any finite assignment (the method nhc used before
/// the sparse one). Returns the value of an optimal assignment of finite entries, or nullopt.
std::optional<long long> dense_hungarian_value(const SignatureMatrix& s) {
  const int n = s.rows();
  int lo = std::numeric_limits<int>::max(), hi = std::numeric_limits<int>::min();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (s.present(i, j)) {
        lo = std::min(lo, s(i, j));
        hi = std::max(hi, s(i, j));
      }
  if (lo > hi) return std::nullopt;
  const long long forbidden = static_cast<long long>(n) * (static_cast<long long>(hi) - lo + 1) + 1;
  auto cost = [&](int i, int j) { return s.present(i, j) ? hi - static_cast<long long>(s(i, j)) : forbidden; };
  const long long inf = std::numeric_limits<long long>::max() / 4;
  std::vector<long long> u(static_cast<std::size_t>(n + 1), 0), v(static_cast<std::size_t>(n + 1), 0);
  std::vector<int> p(static_cast<std::size_t>(n + 1), 0), way(static_cast<std::size_t>(n + 1), 0);
  for (int i = 1; i <= n; ++i) {
    p[0] = i;
    int j0 = 0;
    std::vector<long long> minv(static_cast<std::size_t>(n + 1), inf);
    std::vector<char> used(static_cast<std::size_t>(n + 1), 0);
    do {
      used[static_cast<std::size_t>(j0)] = 1;
      const int i0 = p[static_cast<std::size_t>(j0)];
      long long delta = inf;
      int j1 = 0;
      for (int j = 1; j <= n; ++j) {
        if (used[static_cast<std::size_t>(j)]) continue;
        const long long cur = cost(i0 - 1, j - 1) - u[static_cast<std::size_t>(i0)] - v[static_cast<std::size_t>(j)];
        if (cur < minv[static_cast<std::size_t>(j)]) {
          minv[static_cast<std::size_t>(j)] = cur;
          way[static_cast<std::size_t>(j)] = j0;
        }
        if (minv[static_cast<std::size_t>(j)] < delta) {
          delta = minv[static_cast<std::size_t>(j)];
          j1 = j;
        }
      }
      for (int j = 0; j <= n; ++j) {
        if (used[static_cast<std::size_t>(j)]) {
          u[static_cast<std::size_t>(p[static_cast<std::size_t>(j)])] += delta;
          v[static_cast<std::size_t>(j)] -= delta;
        } else {
          minv[static_cast<std::size_t>(j)] -= delta;
        }
      }
      j0 = j1;
    } while (p[static_cast<std::size_t>(j0)] != 0);
    do {
      const int j1 = way[static_cast<std::size_t>(j0)];
      p[static_cast<std::size_t>(j0)] = p[static_cast<std::size_t>(j1)];
      j0 = j1;
    } while (j0 != 0);
  }
  long long value = 0;
  for (int j = 1; j <= n; ++j) {
    const int i = p[static_cast<std::size_t>(j)] - 1;
    if (!s.present(i, j - 1)) return std::nullopt;
    value += s(i, j - 1);
  }
  return value;
}

/// A sparse random σ: a few entries per row near the diagonal (chain-like) plus scattered ones.
SignatureMatrix random_sparse_matrix(std::mt19937& rng, int n) {
  std::uniform_int_distribution<int> order(0, 3), count(0, 3), column(0, n - 1), near(-2, 2), ten(0, 9);
  SignatureMatrix s(n, n);
  for (int i = 0; i < n; ++i) {
    if (ten(rng) > 0) s.set(i, i, order(rng));  // mostly nonsingular, sometimes not
    for (int k = count(rng); k >= 0; --k) s.set(i, std::clamp(i + near(rng), 0, n - 1), order(rng));
    if (count(rng) == 0) s.set(i, column(rng), order(rng));
  }
  return s;
}

}  // namespace

TEST_CASE("sparse transversal agrees with the dense Hungarian method on larger sparse matrices", "[sigma]") {
  std::mt19937 rng(1709);
  int singular = 0, regular = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const int n = 5 + trial % 76;
    const SignatureMatrix s = random_sparse_matrix(rng, n);
    const auto expected = dense_hungarian_value(s);
    const auto t = highest_value_transversal(s);
    REQUIRE(t.has_value() == expected.has_value());
    if (!t) {
      ++singular;
      REQUIRE(structural_deficiency(s).matching_size < n);
      continue;
    }
    ++regular;
    REQUIRE(t->value == *expected);
    std::vector<int> cols = t->column_of_row;
    std::sort(cols.begin(), cols.end());
    for (int j = 0; j < n; ++j) REQUIRE(cols[static_cast<std::size_t>(j)] == j);
    // Offsets from the sparse transversal satisfy Pryce's conditions and LP duality.
    const Offsets o = pryce_offsets(s, *t);
    long long sum = 0;
    for (int i = 0; i < n; ++i) {
      for (const auto& e : s.row(i))
        REQUIRE(o.d[static_cast<std::size_t>(e.col)] - o.c[static_cast<std::size_t>(i)] >= e.value);
      sum += o.d[static_cast<std::size_t>(i)] - o.c[static_cast<std::size_t>(i)];
    }
    REQUIRE(sum == t->value);
  }
  REQUIRE(singular > 10);
  REQUIRE(regular > 100);
}
