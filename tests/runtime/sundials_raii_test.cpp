// The SUNDIALS owners are move-only and free each object exactly once.
#include <catch2/catch.hpp>

#include <type_traits>
#include <utility>

#include "nhc/runtime/sundials.hpp"

using namespace nhc::runtime::sun;

namespace {
int destroyed = 0;
struct CountingTraits {
  static void destroy(int*) noexcept { ++destroyed; }
};
using Counted = Owner<int*, CountingTraits>;
}  // namespace

TEST_CASE("SUNDIALS owners are move-only", "[runtime]") {
  STATIC_REQUIRE_FALSE(std::is_copy_constructible_v<Vector>);
  STATIC_REQUIRE_FALSE(std::is_copy_assignable_v<Vector>);
  STATIC_REQUIRE(std::is_nothrow_move_constructible_v<Vector>);
  STATIC_REQUIRE(std::is_nothrow_move_assignable_v<Vector>);
  STATIC_REQUIRE_FALSE(std::is_copy_constructible_v<Context>);
  STATIC_REQUIRE_FALSE(std::is_copy_constructible_v<Matrix>);
  STATIC_REQUIRE_FALSE(std::is_copy_constructible_v<LinearSolver>);
  STATIC_REQUIRE_FALSE(std::is_copy_constructible_v<IdaMemory>);
  STATIC_REQUIRE(std::is_nothrow_move_constructible_v<IdaMemory>);
}

TEST_CASE("an owner frees its object once, after moves", "[runtime]") {
  int a = 0, b = 0;
  destroyed = 0;
  {
    Counted first(&a);
    Counted second(std::move(first));
    CHECK_FALSE(first);  // NOLINT(bugprone-use-after-move): moved-from is empty by contract
    CHECK(second.get() == &a);
    Counted third(&b);
    third = std::move(second);  // frees b, takes a
    CHECK(destroyed == 1);
    CHECK(third.get() == &a);
    third = std::move(third);  // self-move keeps it
    CHECK(third.get() == &a);
    CHECK(destroyed == 1);
  }
  CHECK(destroyed == 2);
}

TEST_CASE("real SUNDIALS objects move between owners", "[runtime]") {
  Context ctx = Context::create();
  REQUIRE(ctx);
  Vector v = Vector::create(4, ctx);
  v[2] = 3.5;
  Vector w = std::move(v);
  CHECK_FALSE(v);  // NOLINT(bugprone-use-after-move)
  CHECK(w.size() == 4);
  CHECK(w[2] == 3.5);
  Matrix A = Matrix::dense(4, 4, ctx);
  LinearSolver dense = LinearSolver::dense(w, A, ctx);
  CHECK(dense);
  Matrix S = Matrix::sparse_csc(4, 4, 6, ctx);
  LinearSolver klu = LinearSolver::klu(w, S, ctx);
  CHECK(klu);
  IdaMemory ida = IdaMemory::create(ctx);
  IdaMemory other;
  other = std::move(ida);
  CHECK(other);
  CHECK_FALSE(ida);  // NOLINT(bugprone-use-after-move)
  // Destruction order (solvers, matrices, vectors, then the context) is the reverse of creation.
}
