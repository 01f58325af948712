// The sparse 1-norm condition estimate against the exact dense condition numbers.
#include <catch2/catch.hpp>

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include <random>

#include "nhc/analysis/numeric_evaluation.hpp"

using namespace nhc;

namespace {

/// Sparse random n×n matrix: a dominant-or-not diagonal, a band and a few scattered entries.
Eigen::SparseMatrix<double> random_sparse(std::mt19937& rng, int n, double diagonal) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> col(0, n - 1);
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, diagonal * (1.0 + std::abs(u(rng))));
    if (i + 1 < n) t.emplace_back(i, i + 1, u(rng));
    if (i > 0) t.emplace_back(i, i - 1, u(rng));
    t.emplace_back(i, col(rng), u(rng));
  }
  Eigen::SparseMatrix<double> m(n, n);
  m.setFromTriplets(t.begin(), t.end());
  return m;
}

double exact_condition_1norm(const Eigen::MatrixXd& a) {
  auto norm1 = [](const Eigen::MatrixXd& m) { return m.cwiseAbs().colwise().sum().maxCoeff(); };
  return norm1(a) * norm1(a.inverse());
}

}  // namespace

TEST_CASE("the 1-norm condition estimate is a close lower bound of the exact one", "[sigma]") {
  std::mt19937 rng(4242);
  int within_factor_3 = 0, trials = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 2 + trial % 60;
    const Eigen::SparseMatrix<double> a = random_sparse(rng, n, trial % 4 == 0 ? 0.01 : 1.0);
    const Eigen::MatrixXd dense(a);
    if (dense.fullPivLu().rank() < n) continue;
    ++trials;
    const double exact = exact_condition_1norm(dense);
    const double estimate = condition_estimate_1norm(a);
    INFO("n = " << n << ", exact " << exact << ", estimate " << estimate);
    REQUIRE(estimate <= exact * (1.0 + 1e-8));
    REQUIRE(estimate >= exact / 10.0);
    if (estimate >= exact / 3.0) ++within_factor_3;
    // κ₁/n ≤ κ₂ ≤ n κ₁ against the exact 2-norm condition number.
    const double kappa2 = condition_number(dense);
    REQUIRE(kappa2 <= n * exact * (1.0 + 1e-8));
    REQUIRE(kappa2 >= exact / n * (1.0 - 1e-8));
  }
  REQUIRE(trials > 150);
  REQUIRE(within_factor_3 >= trials * 9 / 10);
}

TEST_CASE("sparse condition numbers: exact 2-norm up to the limit, an estimate above, infinite when singular",
          "[sigma]") {
  std::mt19937 rng(99);
  const Eigen::SparseMatrix<double> small = random_sparse(rng, 30, 1.0);
  const ConditionNumber c = condition_number(small);
  CHECK_FALSE(c.estimated);
  CHECK(c.value == Approx(condition_number(Eigen::MatrixXd(small))).epsilon(1e-12));
  const Eigen::SparseMatrix<double> large = random_sparse(rng, kExactConditionLimit + 50, 1.0);
  const ConditionNumber e = condition_number(large);
  CHECK(e.estimated);
  CHECK(e.value == Approx(exact_condition_1norm(Eigen::MatrixXd(large))).epsilon(0.7));
  Eigen::SparseMatrix<double> singular = random_sparse(rng, kExactConditionLimit + 10, 1.0);
  singular.prune([](Eigen::Index i, Eigen::Index, double) { return i != 7; });  // a zero row
  CHECK_FALSE(condition_number(singular).value < 1e12);
}
