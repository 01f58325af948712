// The sparse minimum-norm Gauss–Newton step (large systems with a sparse Jacobian) against the
// dense complete orthogonal decomposition (constraint_solver.hpp).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "nhc/base/constraint_solver.hpp"

using namespace nhc;

TEST_CASE("sparse and dense Gauss-Newton steps reach the same point", "[runtime]") {
  // g_i(y) = y_i + 0.2 sin y_{i+1} + 0.1 y_{i+3}^2 − b_i on m = 300 constraints in n = 305 values,
  // the last 5 fixed: m · n_free above kSparseStepSize.
  const int m = 300, n = 305;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(1.0, 1.2);
  std::vector<double> b(static_cast<std::size_t>(m));
  for (double& v : b) v = u(rng);
  base::ConstraintFunctions f;
  f.count = m;
  f.size = n;
  f.values = [&](const double* y, double* g) {
    for (int i = 0; i < m; ++i)
      g[i] = y[i] + 0.2 * std::sin(y[i + 1]) + 0.1 * y[i + 3] * y[i + 3] - b[static_cast<std::size_t>(i)];
  };
  auto entries = [&](const double* y, std::vector<base::SparseEntry>& out) {
    for (int i = 0; i < m; ++i) {
      out.push_back({i, i, 1.0});
      out.push_back({i, i + 1, 0.2 * std::cos(y[i + 1])});
      out.push_back({i, i + 3, 0.2 * y[i + 3]});
    }
  };
  int dense_calls = 0;
  f.jacobian = [&](const double* y, double* jac) {
    ++dense_calls;
    std::fill(jac, jac + static_cast<std::ptrdiff_t>(m) * n, 0.0);
    std::vector<base::SparseEntry> list;
    entries(y, list);
    for (const auto& e : list) jac[static_cast<std::ptrdiff_t>(e.col) * m + e.row] += e.value;
  };
  std::vector<double> scale(static_cast<std::size_t>(n), 1.0);
  for (int k = m; k < n; ++k) scale[static_cast<std::size_t>(k)] = 0.0;  // the tail fixed
  REQUIRE(static_cast<long long>(m) * (n - 5) > base::kSparseStepSize);
  std::vector<double> dense_y(static_cast<std::size_t>(n), 1.0), sparse_y = dense_y;
  const auto dense = base::solve_constraints(f, dense_y.data(), scale, 1e-10);
  REQUIRE(dense_calls == dense.iterations);
  dense_calls = 0;
  f.sparse_jacobian = entries;
  const auto sparse = base::solve_constraints(f, sparse_y.data(), scale, 1e-10);
  INFO("dense status " << static_cast<int>(dense.status) << " residual " << dense.residual_before << " -> "
                       << dense.residual_after << " after " << dense.iterations);
  REQUIRE(dense.converged());
  REQUIRE(sparse.converged());
  CHECK(dense_calls == 0);  // every step was taken sparsely
  CHECK(sparse.iterations == dense.iterations);
  for (int k = 0; k < n; ++k)
    CHECK(sparse_y[static_cast<std::size_t>(k)] == Approx(dense_y[static_cast<std::size_t>(k)]).margin(1e-11));
}
