// [jit]: nhc::jit — scenes built in code, compiled and loaded in one process.
//
// Closed form (models.md, Appell–Hamel under Chetaev's model; k = b/a, v = |(x', y')|): from
// x = y = z = 0, x' = 1, y' = 0.5 the horizontal direction stays fixed, the speed falls as
// v = v0 − g k t/(1 + k^2), z' = k v, λ = m g/(1 + k^2), and v reaches 0 at
// t* = v0 (a^2 + b^2)/(g a b). Two scenes of the SAME name (one generated namespace) with
// different b must load as two models with their own tables and their own answers.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <string>

#include "command_runner.hpp"
#include "nhc/io/shell.hpp"
#include "nhc/jit.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene_builder.hpp"

namespace fs = std::filesystem;

namespace {

constexpr double m = 1.0, g = 9.81, a = 1.0, vx0 = 1.0, vy0 = 0.5;

nhc::Scene appell_hamel(double b) {
  return nhc::SceneBuilder("appell_hamel")
      .coordinates({"x", "y", "z"})
      .parameter("m", m)
      .parameter("g", g)
      .parameter("a", a)
      .parameter("b", b)
      .lagrangian("m/2*(x'^2 + y'^2 + z'^2) - m*g*z")
      .constraint("z' - b/a*sqrt(x'^2 + y'^2)")
      .initial("x", {0.0, vx0})
      .initial("y", {0.0, vy0})
      .initial("z", {0.0})
      .build();
}

double t_star(double b) { return std::hypot(vx0, vy0) * (a * a + b * b) / (g * a * b); }

/// A cache directory of this test's own, empty.
fs::path fresh_cache(const std::string& name) {
  const fs::path dir = fs::path(NHC_BINARY_DIR) / "tests" / "jit" / name;
  fs::remove_all(dir);
  return dir;
}

struct Outcome {
  double worst_relative_error = 0;  ///< against the closed form, on [0, 0.9 t*]
  double z_dot_end = 0;             ///< z' at 0.9 t*
};

Outcome integrate(const nhc::runtime::Model& model, const nhc::Scene& scene, double b) {
  using namespace nhc::runtime;
  const double k = b / a, v0 = std::hypot(vx0, vy0), decel = g * k / (1 + k * k), t_end = 0.9 * t_star(b);
  IntegratorOptions options;
  options.rtol = 1e-8;
  options.atol = 1e-10;
  const RunResult run =
      simulate(model, model.default_parameters(), initial_state_from(model, scene.initial.t0, scene.initial.values),
               output_times(0.0, t_end, 50), options);
  REQUIRE_FALSE(run.failure);
  REQUIRE(run.samples.back().t == Approx(t_end));
  Outcome out;
  for (const Sample& sample : run.samples) {
    const double t = sample.t, arc = v0 * t - decel * t * t / 2, v = v0 - decel * t;
    const double exact[] = {vx0 / v0 * arc, vx0 / v0 * v, vy0 / v0 * arc,     vy0 / v0 * v,
                            k * arc,        k * v,        m * g / (1 + k * k)};
    const char* names[] = {"x", "x'", "y", "y'", "z", "z'", "lambda1"};
    for (int i = 0; i < 7; ++i) {
      const double value = sample.y[static_cast<std::size_t>(i)];
      REQUIRE(model.state_name(i) == names[i]);
      out.worst_relative_error =
          std::max(out.worst_relative_error, std::abs(value - exact[i]) / std::max(1.0, std::abs(exact[i])));
    }
  }
  out.z_dot_end = run.samples.back().y[5];
  return out;
}

}  // namespace

TEST_CASE("two scenes of the same name load as two models, each with its own answer", "[jit]") {
  nhc::jit::BuildOptions options;
  options.compile.cache_directory = fresh_cache("same-name-cache");
  const nhc::Scene steep = appell_hamel(0.5), shallow = appell_hamel(0.25);
  const nhc::jit::LoadedModel first = nhc::jit::build(steep, nhc::ModelKind::chetaev, options);
  const nhc::jit::LoadedModel second = nhc::jit::build(shallow, nhc::ModelKind::chetaev, options);

  // One namespace, two shared objects, two tables.
  CHECK(first.header().namespace_name == second.header().namespace_name);
  CHECK(first.library().path != second.library().path);
  CHECK(&first.model().table() != &second.model().table());
  CHECK(first.model().table().residual != second.model().table().residual);
  const auto b_of = [](const nhc::runtime::Model& model) {
    return model.default_parameters()[static_cast<std::size_t>(model.parameter_index("b"))];
  };
  CHECK(b_of(first.model()) == 0.5);
  CHECK(b_of(second.model()) == 0.25);

  const Outcome one = integrate(first.model(), steep, 0.5);
  const Outcome two = integrate(second.model(), shallow, 0.25);
  CHECK(one.worst_relative_error < 1e-6);
  CHECK(two.worst_relative_error < 1e-6);
  // z'(0.9 t*) = k v0 (1 − 0.9) for each b: different numbers, each the scene's own.
  CHECK(one.z_dot_end == Approx(0.5 * std::hypot(vx0, vy0) * 0.1).epsilon(1e-6));
  CHECK(two.z_dot_end == Approx(0.25 * std::hypot(vx0, vy0) * 0.1).epsilon(1e-6));

  // The cache: the same scene again is found, not compiled.
  const nhc::jit::LoadedModel again = nhc::jit::build(steep, nhc::ModelKind::chetaev, options);
  CHECK(again.library().reused);
  CHECK(again.library().path == first.library().path);
}

TEST_CASE("a hand-written header compiles and loads beside the generated model of its scene", "[jit]") {
  nhc::jit::CompileOptions options;
  options.cache_directory = fresh_cache("handwritten-cache");
  const fs::path handwritten = fs::path(NHC_SOURCE_DIR) / "tests/runtime/handwritten/appell_hamel_chetaev.hpp";
  const nhc::jit::CompiledLibrary library = nhc::jit::compile_header_file(handwritten, options);
  const nhc::runtime::Model hand = nhc::runtime::Model::load(library.path.string());
  nhc::jit::BuildOptions build_options;
  build_options.compile = options;
  const nhc::Scene scene = appell_hamel(0.5);
  const nhc::jit::LoadedModel generated = nhc::jit::build(scene, nhc::ModelKind::chetaev, build_options);
  // Same namespace nhc_gen::appell_hamel_chetaev in both: still two tables.
  CHECK(&hand.table() != &generated.model().table());
  CHECK(hand.n_states() == generated.model().n_states());
  CHECK(integrate(hand, scene, 0.5).worst_relative_error < 1e-6);
}

TEST_CASE("no shared object nhc::jit builds has an STB_GNU_UNIQUE symbol", "[jit]") {
  nhc::jit::CompileOptions options;
  options.cache_directory = fresh_cache("readelf-cache");
  nhc::jit::BuildOptions build_options;
  build_options.compile = options;
  for (double b : {0.5, 0.25}) nhc::jit::build(appell_hamel(b), nhc::ModelKind::chetaev, build_options);
  build_options.jacobian = nhc::JacobianKind::sparse;
  nhc::jit::build(appell_hamel(0.5), nhc::ModelKind::chetaev, build_options);
  nhc::jit::compile_header_file(fs::path(NHC_SOURCE_DIR) / "tests/runtime/handwritten/appell_hamel_chetaev.hpp",
                                options);
  nhc::jit::CompileOptions chain = options;
  chain.flags.push_back("-DNHC_BENCH_CHAIN_N=2");
  nhc::jit::compile_header_file(fs::path(NHC_SOURCE_DIR) / "bench/knife_chain_handwritten.hpp", chain);

  int libraries = 0;
  for (const auto& entry : fs::directory_iterator(options.cache_directory)) {
    if (entry.path().extension() != ".so") continue;
    ++libraries;
    INFO(entry.path());
    std::string symbols;
    REQUIRE(nhc::test::run_command("readelf -Ws " + nhc::shell_quote(entry.path().string()), symbols) == 0);
    CHECK(symbols.find("nhc_model_table_get") != std::string::npos);
    CHECK(symbols.find(" UNIQUE ") == std::string::npos);
    // Exported (dynamic, defined, default visibility): the table's entry point and nothing of
    // the model's namespace.
    std::string dynamic;
    REQUIRE(nhc::test::run_command("readelf -W --dyn-syms " + nhc::shell_quote(entry.path().string()), dynamic) == 0);
    CHECK(dynamic.find("nhc_gen") == std::string::npos);
    CHECK(dynamic.find("_ZN7nhc_gen") == std::string::npos);
  }
  CHECK(libraries == 5);
}
