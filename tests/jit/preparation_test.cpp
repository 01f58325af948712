// [jit][preparation]: a run's preparation (app/nhc/app/preparation.hpp) derives the model and runs
// the Σ-method once: the initial-point check's analysis is what jit::build reduces, so a simulate
// with the scene cache off counts one derive_model() and one analyze_structure(). The model built
// from the analysis equals the one built alone (same header text).
#include <catch2/catch.hpp>

#include <cstdlib>
#include <string>

#include "nhc/analysis/structural_analysis.hpp"
#include "nhc/app/preparation.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/jit.hpp"
#include "nhc/scene/scene_builder.hpp"

namespace {

nhc::Scene appell_hamel() {
  return nhc::parse_scene(
      "name = \"appell_hamel\"\n"
      "coordinates = [\"x\", \"y\", \"z\"]\n"
      "lagrangian = \"m/2*(x'^2 + y'^2 + z'^2) - m*g*z\"\n"
      "constraints = [\"z' - b/a*sqrt(x'^2 + y'^2)\"]\n"
      "[parameters]\nm = 1.0\ng = 9.81\na = 1.0\nb = 0.5\n"
      "[initial]\nt0 = 0.0\nx = [0.0, 1.0]\ny = [0.0, 0.5]\nz = [0.0]\n",
      "appell_hamel.toml");
}

nhc::jit::BuildOptions uncached_interpreted() {
  nhc::jit::BuildOptions o;
  o.backend = nhc::jit::Backend::interpreted;  // nothing to compile: the count is the point
  o.scene_cache = false;
  return o;
}

}  // namespace

TEST_CASE("a run's preparation derives and analyses the model once", "[jit][preparation]") {
  ::setenv("NHC_SCENE_CACHE", "off", 1);  // the initial-point check is not taken from the cache
  const nhc::Scene scene = appell_hamel();
  for (const nhc::ModelKind kind : {nhc::ModelKind::chetaev, nhc::ModelKind::vakonomic}) {
    INFO("model " << nhc::to_string(kind));
    const long derived_before = nhc::derive_model_calls();
    const long analysed_before = nhc::analyze_structure_calls();
    nhc::app::Preparation preparation(scene, kind);
    const nhc::app::InitialPointCheck check = nhc::app::check_initial_point(preparation, false);
    CHECK(check.problems_at_t0.empty());
    REQUIRE(preparation.structure() != nullptr);
    const nhc::jit::LoadedModel built = preparation.build(scene, uncached_interpreted());
    CHECK(nhc::derive_model_calls() - derived_before == 1);
    CHECK(nhc::analyze_structure_calls() - analysed_before == 1);

    // Built alone, the model derives and analyses again, into the same header.
    const long derived_alone = nhc::derive_model_calls();
    const nhc::jit::LoadedModel alone = nhc::jit::build(scene, kind, uncached_interpreted());
    CHECK(nhc::derive_model_calls() - derived_alone == 1);
    CHECK(alone.header().text == built.header().text);
  }
  ::unsetenv("NHC_SCENE_CACHE");
}
