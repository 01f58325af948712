// Singular cases are reported in words, not crashed on: the vakonomic particle at
// λ' = 1, the holder particle at λ = 0, vakonomic Appell–Hamel where m v = λ b/a, a suslov
// model with identically singular ∂f/∂q'^dep, and a structurally singular system.
#include <catch2/catch.hpp>

#include "analysis_test_support.hpp"
#include "nhc/analysis/index1_reduction.hpp"
#include "nhc/analysis/model_analysis.hpp"
#include "nhc/errors.hpp"

using namespace nhc;
using Catch::Matchers::Contains;

namespace {

ModelAnalysis analysis(const std::string& scene_path, ModelKind kind) {
  const Scene s = test::scene_at(scene_path);
  return analyze_model(s, derive_model(s, kind));
}

}  // namespace

TEST_CASE("vakonomic particle at lambda' = 1: singular Jacobian at t0", "[sigma]") {
  // R_i = (λ' − 1) q_i'' + λ'' q_i': at λ' = 1 the rows R_i of J = [[(λ'−1) I, q'], [q'ᵀ, 0]]
  // reduce to (0, q'), rank 2 of 4; the q'' orthogonal to q' are not determined.
  const ModelAnalysis m = analysis("tests/analysis/scenes/particle_vakonomic_singular.toml", ModelKind::vakonomic);
  REQUIRE(m.errors.size() == 1);
  CHECK_THAT(m.errors[0],
             Contains("singular at t0") && Contains("R_q1") && Contains("q1''") && Contains("rank 2 of 4"));
  CHECK(m.jacobian_condition > 1e12);
  // The same scene with λ'(0) = 0 (examples/particle.toml) is regular.
  CHECK(analysis("examples/particle.toml", ModelKind::vakonomic).ok());
}

TEST_CASE("holder particle at lambda = 0: singular Jacobian at t0", "[sigma]") {
  // J = [[−2λ I, −q'], [q'ᵀ, 0]] (columns q''', λ''), det = 4 λ² |q'|²: singular at λ = 0.
  const ModelAnalysis m = analysis("examples/particle.toml", ModelKind::holder);
  REQUIRE(m.errors.size() == 1);
  CHECK_THAT(m.errors[0], Contains("holder") && Contains("R_q1") && Contains("q1'''"));
  // The structure itself is fine: the reduction still exists (singular only at such points).
  const Scene s = test::scene_at("examples/particle.toml");
  CHECK_NOTHROW(reduce_to_index1(s, derive_model(s, ModelKind::holder)));
}

TEST_CASE("vakonomic Appell-Hamel where m v = lambda b/a", "[sigma]") {
  // m = 1, v = 1, k = 1/2, λ = 2: the row R_y loses its y'' coefficient −m + k λ / v.
  const ModelAnalysis m = analysis("examples/appell_hamel_vakonomic_singular.toml", ModelKind::vakonomic);
  REQUIRE(m.errors.size() == 1);
  CHECK_THAT(m.errors[0], Contains("R_y") && Contains("y''") && Contains("rank 3 of 4"));
  // Chetaev on the same data is regular.
  CHECK(analysis("examples/appell_hamel_vakonomic_singular.toml", ModelKind::chetaev).ok());
}

TEST_CASE("suslov with identically singular df/dq'^dep is not applicable", "[sigma]") {
  const ModelAnalysis m = analysis("tests/analysis/scenes/suslov_singular.toml", ModelKind::suslov);
  CHECK_FALSE(m.applicable);
  REQUIRE(m.errors.size() == 1);
  CHECK_THAT(m.errors[0], Contains("not applicable") && Contains("identically singular"));
  const Scene s = test::scene_at("tests/analysis/scenes/suslov_singular.toml");
  CHECK_THROWS_AS(reduce_to_index1(s, derive_model(s, ModelKind::suslov)), MathError);
}

TEST_CASE("structurally singular system: which equations, which unknowns", "[sigma]") {
  // L = x'²/2 + c y: R_y = c has no unknown; chetaev σ row R_y is all −∞.
  const Scene s = test::scene_at("tests/analysis/scenes/structurally_singular.toml");
  const StructuralAnalysis a = test::structure_of(s, ModelKind::chetaev);
  REQUIRE(a.structurally_singular);
  CHECK(a.deficiency.matching_size == 2);
  CHECK_THAT(a.singular_reason, Contains("R_y") && Contains("no unknown") && Contains("y is left"));
  CHECK_THROWS_WITH(reduce_to_index1(s, derive_model(s, ModelKind::chetaev)),
                    Contains("structurally singular") && Contains("R_y"));
}
