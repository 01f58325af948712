// [intermediates]: scenes read with their definitions kept as named intermediates
// (SceneOptions::keep_definitions, docs/intermediates.md) derive, reduce, generate, compile and
// integrate to the same motion as the same scenes with definitions substituted — a second
// derivation of every equation, through the chain rule instead of through expansion — and the
// first one checked against the closed form the scene carries ([reference]).
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "nhc/jit.hpp"
#include "nhc/runtime/runtime.hpp"

namespace fs = std::filesystem;

namespace {

std::string read_example(const std::string& name) {
  std::ifstream in(fs::path(NHC_SOURCE_DIR) / "examples" / name);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

nhc::jit::BuildOptions options_in(const std::string& cache) {
  nhc::jit::BuildOptions options;
  options.compile.cache_directory = fs::path(NHC_BINARY_DIR) / "tests" / "jit" / cache;
  options.scene_cache = false;
  return options;
}

/// The final state of the scene's own [simulate] run.
std::vector<double> final_state(const nhc::jit::LoadedModel& built, const nhc::Scene& scene) {
  using namespace nhc::runtime;
  IntegratorOptions options;
  options.rtol = 1e-10;
  options.atol = 1e-12;
  const Model& model = built.model();
  const RunResult run =
      simulate(model, model.default_parameters(), initial_state_from(model, scene.initial.t0, scene.initial.values),
               output_times(scene.initial.t0, scene.simulate.t_end, 20), options);
  REQUIRE_FALSE(run.failure);
  REQUIRE(run.samples.back().t == Approx(scene.simulate.t_end));
  return run.samples.back().y;
}

/// The scene read with every definition substituted (`--expand`).
nhc::SceneOptions expanded() {
  nhc::SceneOptions options;
  options.keep_definitions = false;
  return options;
}

}  // namespace

TEST_CASE("definitions kept as intermediates give the motion of definitions substituted", "[jit][intermediates]") {
  for (const std::string example :
       {"constant_speed_definitions.toml", "rolling_ball.toml", "rolling_disk.toml", "chaplygin_sleigh.toml"}) {
    INFO(example);
    const std::string text = read_example(example);
    const nhc::Scene substituted = nhc::parse_scene(text, example, expanded());
    const nhc::Scene kept = nhc::parse_scene(text, example);
    const nhc::ModelKind kind = substituted.simulate.model.value_or(nhc::ModelKind::chetaev);
    const nhc::jit::LoadedModel a = nhc::jit::build(substituted, kind, options_in("intermediates-cache"));
    const nhc::jit::LoadedModel b = nhc::jit::build(kept, kind, options_in("intermediates-cache"));
    REQUIRE(a.model().n_states() == b.model().n_states());
    const std::vector<double> ya = final_state(a, substituted), yb = final_state(b, kept);
    for (std::size_t i = 0; i < ya.size(); ++i) {
      INFO(a.model().state_name(static_cast<int>(i)));
      CHECK(yb[i] == Approx(ya[i]).epsilon(1e-7).margin(1e-9));
    }
    WARN(example << ": operations after CSE " << a.header().after_cse.total() << " substituted, "
                 << b.header().after_cse.total() << " kept");
  }
}

/// The definition chain d0 = x' + y + 1, d_k = d_{k-1}^2 + x, L = d_n, with the constraint x' = y.
std::string definition_chain(int n) {
  std::string text = "name = \"definition_chain\"\ncoordinates = [\"x\", \"y\"]\nlagrangian = \"d" + std::to_string(n) +
                     "\"\nconstraints = [\"x' - y\"]\n[definitions]\nd0 = \"x' + y + 1\"\n";
  for (int k = 1; k <= n; ++k)
    text += "d" + std::to_string(k) + " = \"d" + std::to_string(k - 1) + "*d" + std::to_string(k - 1) + " + x\"\n";
  return text + "[initial]\nx = [-0.3, -0.4]\ny = [-0.4]\n[simulate]\nt_end = 0.1\n";
}

TEST_CASE("a chain of 24 definitions derives and generates in proportion to its length", "[jit][intermediates]") {
  // Substituted, d5 already expands past the term limit (d24 has degree 2^24); kept, each link
  // adds the same few operations to each function: the operations grow linearly with n.
  CHECK_THROWS_AS(nhc::parse_scene(definition_chain(24), "chain.toml", expanded()), nhc::InputError);
  std::vector<long long> operations;  // n = 6, 12, 18, 24
  for (int n = 6; n <= 24; n += 6) {
    const nhc::Scene kept = nhc::parse_scene(definition_chain(n), "chain.toml");
    const nhc::jit::LoadedModel built =
        nhc::jit::build(kept, nhc::ModelKind::chetaev, options_in("intermediates-cache"));
    operations.push_back(built.header().after_cse.total());
    WARN("chain of " << n << ": operations after CSE " << operations.back() << ", header " << built.header().text.size()
                     << " bytes");
  }
  // Linear: every 6 links add about the same number of operations (measured 1242, 1406, 1283:
  // the first links are small enough to be substituted, and the size threshold names a
  // derivative every few links); expanded, the count would grow without bound (the scene
  // above is refused), and quadratic growth would double each increment.
  for (std::size_t k = 2; k < operations.size(); ++k)
    CHECK(static_cast<double>(operations[k] - operations[k - 1]) ==
          Approx(static_cast<double>(operations[1] - operations[0])).epsilon(0.2));
}

TEST_CASE("the Whipple bicycle with its definitions kept: a small header that conserves energy",
          "[jit][intermediates]") {
  // Substituted, the bicycle's header had 639,587 operations and 4.5 MB; kept, the
  // targets for the whole header: at most 30,000 operations and 600 kB. The motion
  // is checked by its energy (T + V, [invariants]), conserved by rolling without slip; the
  // eigenvalues of its upright motion by Meijaard et al.'s Table 2 (tests/linearize).
  const std::string text = read_example("whipple/whipple_bicycle.toml");
  const nhc::Scene kept = nhc::parse_scene(text, "whipple_bicycle.toml");
  const nhc::jit::LoadedModel built = nhc::jit::build(kept, nhc::ModelKind::chetaev, options_in("intermediates-cache"));
  WARN("Whipple bicycle, kept: operations after CSE " << built.header().after_cse.total() << ", header "
                                                      << built.header().text.size() << " bytes");
  CHECK(built.header().after_cse.total() <= 30000);
  CHECK(built.header().text.size() <= 600000);
  using namespace nhc::runtime;
  const Model& model = built.model();
  REQUIRE(model.n_invariants() == 1);
  IntegratorOptions options;
  options.rtol = 1e-10;
  options.atol = 1e-12;
  const RunResult run =
      simulate(model, model.default_parameters(), initial_state_from(model, kept.initial.t0, kept.initial.values),
               output_times(kept.initial.t0, kept.simulate.t_end, 50), options);
  REQUIRE_FALSE(run.failure);
  const std::vector<double> p = model.default_parameters();
  const double e0 = observe(model, p, run.samples.front()).invariants.at(0);
  double drift = 0;
  for (const Sample& sample : run.samples)
    drift = std::max(drift, std::abs(observe(model, p, sample).invariants.at(0) - e0));
  WARN("energy " << e0 << ", drift " << drift);
  CHECK(drift <= 1e-7 * std::max(1.0, std::abs(e0)));
}

// Hidden from the default run: the substituted bicycle takes about 100 s to derive and compile.
// ctest runs it as jit:whipple_kept_equals_substituted (label slow).
TEST_CASE("the Whipple bicycle kept and substituted move alike", "[.whipple-kept]") {
  const std::string text = read_example("whipple/whipple_bicycle.toml");
  const nhc::Scene kept = nhc::parse_scene(text, "whipple_bicycle.toml");
  const nhc::Scene substituted = nhc::parse_scene(text, "whipple_bicycle.toml", expanded());
  const nhc::jit::LoadedModel b = nhc::jit::build(kept, nhc::ModelKind::chetaev, options_in("intermediates-cache"));
  const nhc::jit::LoadedModel a =
      nhc::jit::build(substituted, nhc::ModelKind::chetaev, options_in("intermediates-cache"));
  WARN("operations after CSE: " << a.header().after_cse.total() << " substituted, " << b.header().after_cse.total()
                                << " kept");
  const std::vector<double> ya = final_state(a, substituted), yb = final_state(b, kept);
  for (std::size_t i = 0; i < ya.size(); ++i) {
    INFO(a.model().state_name(static_cast<int>(i)));
    CHECK(yb[i] == Approx(ya[i]).epsilon(1e-7).margin(1e-9));
  }
}
