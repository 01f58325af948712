// The Hungarian transversal and Pryce's offsets against brute force, and the Σ-method on the
// textbook index-3 pendulum (Pryce 2001, §2 example).
#include <catch2/catch.hpp>

#include <algorithm>
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
  auto jet = std::make_shared<JetSpace>(std::vector<std::string>{"x", "y"}, 1,
                                        std::vector<std::string>{"g", "L"});
  DaeSystem sys;
  sys.jet = jet;
  sys.unknowns = {{VariableKind::coordinate, 0, "x"}, {VariableKind::coordinate, 1, "y"},
                  {VariableKind::multiplier, 0, "lambda1"}};
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
