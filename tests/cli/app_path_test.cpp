// [cli][app]: nhc simulate takes the application layer's path to a model (app::prepare_and_build, the
// path of Python's Scene.build as well; python/tests/test_front_ends.py): with the scene cache off,
// one run derives its model and runs the Σ-method once, the initial-point check's analysis being
// what the build reduces.
#include <catch2/catch.hpp>

#include <cstdlib>

#include "nhc/analysis/structural_analysis.hpp"
#include "nhc/derive/models.hpp"
#include "simulate_command.hpp"

TEST_CASE("nhc simulate derives and analyses its model once", "[cli][app]") {
  ::setenv("NHC_SCENE_CACHE", "off", 1);
  nhc::cli::SimulateOptions options;
  options.run.scene_path = std::string(NHC_SOURCE_DIR) + "/examples/appell_hamel.toml";
  options.run.backend = "interpreted";  // nothing to compile: the count is the point
  options.run.t_end = 0.1;
  const long derived = nhc::derive_model_calls();
  const long analysed = nhc::analyze_structure_calls();
  CHECK(nhc::cli::run_simulate(options) == 0);
  CHECK(nhc::derive_model_calls() - derived == 1);
  CHECK(nhc::analyze_structure_calls() - analysed == 1);
  ::unsetenv("NHC_SCENE_CACHE");
}
