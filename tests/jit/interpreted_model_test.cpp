// [jit][interpreter]: the interpreted model (jit/interpreted_model.hpp) against the compiled one
// of the same header — an independent path for the numbers: the C++ compiler's code. Every
// function of the table at points drawn from a fixed seed, then whole runs; and the compile
// behind an interpreted run (compile_behind.hpp): the switch changes no number, and the next
// build of the scene is compiled.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "nhc/jit.hpp"
#include "nhc/jit/compile_behind.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"

namespace fs = std::filesystem;
using nhc::jit::Backend;

namespace {

nhc::jit::BuildOptions options_in(const std::string& cache, Backend backend) {
  nhc::jit::BuildOptions options;
  options.reduced_form = true;  // the multiplier-free form's functions are compared too
  options.compile.cache_directory = fs::path(NHC_BINARY_DIR) / "tests" / "jit" / cache;
  options.scene_cache = false;
  options.backend = backend;
  return options;
}

/// |a − b| ≤ 1e-12 (1 + |b|) entry by entry.
void require_close(const std::vector<double>& a, const std::vector<double>& b, const std::string& what) {
  REQUIRE(a.size() == b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    INFO(what << " entry " << k << ": interpreted " << a[k] << ", compiled " << b[k]);
    REQUIRE(std::abs(a[k] - b[k]) <= 1e-12 * (1 + std::abs(b[k])));
  }
}

/// Every function both tables have, at `points` points (y, y', p, t, cj from a fixed seed).
void compare_tables(const nhc::runtime::Model& interpreted, const nhc::runtime::Model& compiled, int points) {
  const nhc_model_table& I = interpreted.table();
  const nhc_model_table& C = compiled.table();
  REQUIRE(I.n_states == C.n_states);
  REQUIRE(I.n_parameters == C.n_parameters);
  REQUIRE(I.n_inputs == C.n_inputs);
  for (int i = 0; i < I.n_states; ++i) {
    REQUIRE(std::string(I.state_names[i]) == C.state_names[i]);
    REQUIRE(I.differential_id[i] == C.differential_id[i]);
  }
  const auto n = static_cast<std::size_t>(C.n_states);
  const auto np = static_cast<std::size_t>(C.n_parameters + C.n_inputs);
  std::mt19937_64 random(20261126);
  std::uniform_real_distribution<double> draw(0.2, 1.3);  // away from the singular sets at 0
  for (int point = 0; point < points; ++point) {
    std::vector<double> y(n), yp(n), p(np + 1);
    for (double& v : y) v = draw(random);
    for (double& v : yp) v = draw(random);
    for (double& v : p) v = draw(random);
    const double t = draw(random), cj = 10 * draw(random);
    auto both = [&](std::size_t size, auto&& call, const std::string& what) {
      std::vector<double> a(size + 1, -7.0), b(size + 1, -7.0);  // zero fills must be the function's
      call(I, a.data());
      call(C, b.data());
      require_close(a, b, what);
    };
    both(
        n, [&](const nhc_model_table& T, double* out) { T.residual(t, y.data(), yp.data(), p.data(), out); },
        "residual");
    if (C.jacobian)
      both(
          n * n, [&](const nhc_model_table& T, double* out) { T.jacobian(t, y.data(), yp.data(), cj, p.data(), out); },
          "dense Jacobian");
    if (C.jacobian_values) {
      REQUIRE(I.jacobian_nnz == C.jacobian_nnz);
      REQUIRE(std::equal(C.jacobian_colptr, C.jacobian_colptr + n + 1, I.jacobian_colptr));
      both(
          static_cast<std::size_t>(C.jacobian_nnz),
          [&](const nhc_model_table& T, double* out) { T.jacobian_values(t, y.data(), yp.data(), cj, p.data(), out); },
          "sparse Jacobian");
    }
    const auto h = static_cast<std::size_t>(C.n_hidden);
    if (h > 0) {
      both(
          h, [&](const nhc_model_table& T, double* out) { T.hidden_constraints(t, y.data(), p.data(), out); },
          "hidden constraints");
      both(
          h * n,
          [&](const nhc_model_table& T, double* out) { T.hidden_constraints_jacobian(t, y.data(), p.data(), out); },
          "hidden-constraint Jacobian");
    }
    if (C.n_invariants > 0)
      both(
          static_cast<std::size_t>(C.n_invariants),
          [&](const nhc_model_table& T, double* out) { T.invariants(t, y.data(), yp.data(), p.data(), out); },
          "invariants");
    if (C.n_singular > 0)
      both(
          static_cast<std::size_t>(C.n_singular),
          [&](const nhc_model_table& T, double* out) { T.singular_quantities(t, y.data(), p.data(), out); },
          "singular quantities");
    if (C.residual_parameter_jacobian) {
      REQUIRE(I.residual_parameter_jacobian);
      both(
          n * static_cast<std::size_t>(C.n_parameters),
          [&](const nhc_model_table& T, double* out) {
            T.residual_parameter_jacobian(t, y.data(), yp.data(), p.data(), out);
          },
          "dF/dp");
    }
    if (C.n_inputs > 0)
      both(
          static_cast<std::size_t>(C.n_inputs),
          [&](const nhc_model_table& T, double* out) { T.default_inputs(t, p.data(), out); }, "default inputs");
    // Reduced-form additions: q from y, the independent speeds from y'.
    REQUIRE(I.n_speeds == C.n_speeds);
    if (C.n_speeds > 0) {
      REQUIRE(I.mass_matrix);
      REQUIRE(std::equal(C.speed_coordinate, C.speed_coordinate + C.n_speeds, I.speed_coordinate));
      const auto k = static_cast<std::size_t>(C.n_speeds);
      const std::vector<double> q(y.begin(), y.begin() + C.n_coordinates), u(yp.begin(), yp.begin() + C.n_speeds);
      both(
          static_cast<std::size_t>(C.n_coordinates),
          [&](const nhc_model_table& T, double* out) { T.velocities(t, q.data(), u.data(), p.data(), out); },
          "velocities");
      both(
          k * k, [&](const nhc_model_table& T, double* out) { T.mass_matrix(t, q.data(), u.data(), p.data(), out); },
          "mass matrix");
      both(
          k, [&](const nhc_model_table& T, double* out) { T.forcing(t, q.data(), u.data(), p.data(), out); },
          "forcing");
    }
  }
}

std::vector<double> final_state(const nhc::runtime::Model& model, const nhc::Scene& scene) {
  using namespace nhc::runtime;
  IntegratorOptions options;
  options.rtol = 1e-10;
  options.atol = 1e-12;
  const RunResult run =
      simulate(model, model.default_parameters(), initial_state_from(model, scene.initial.t0, scene.initial.values),
               output_times(scene.initial.t0, scene.simulate.t_end, 20), options);
  REQUIRE_FALSE(run.failure);
  return run.samples.back().y;
}

const char* const kDriven =
    "name = \"driven_pendulum\"\ncoordinates = [\"x\", \"y\"]\nparameters = { k = 2.0, c = 0.5 }\n"
    "lagrangian = \"(x'^2 + y'^2)/2 - k*(x^2 + y^2)/2\"\nconstraints = [\"x*x' + y*y'\"]\n"
    "[inputs]\nu = \"c*sin(2*t)\"\n[forces]\nx = \"u\"\n[initial]\nx = [1.0, 0.0]\ny = [0.0, 0.5]\n"
    "[invariants]\nradius = \"x^2 + y^2\"\n[simulate]\nt_end = 2.0\n";

}  // namespace

TEST_CASE("interpreted and compiled models agree function by function and run by run", "[jit][interpreter]") {
  struct Case {
    std::string file;  ///< under examples/, or "" for kDriven
    nhc::ModelKind kind;
    bool sensitivities;
  };
  const Case cases[] = {{"appell_hamel.toml", nhc::ModelKind::chetaev, true},
                        {"appell_hamel.toml", nhc::ModelKind::vakonomic, false},
                        {"rolling_disk.toml", nhc::ModelKind::chetaev, false},
                        {"knife_edge.toml", nhc::ModelKind::holder, false},
                        {"", nhc::ModelKind::chetaev, true}};
  for (const Case& c : cases) {
    const nhc::Scene scene = c.file.empty()
                                 ? nhc::parse_scene(kDriven, "driven_pendulum.toml")
                                 : nhc::load_scene((fs::path(NHC_SOURCE_DIR) / "examples" / c.file).string());
    INFO(scene.name << ", " << nhc::to_string(c.kind));
    nhc::jit::BuildOptions interpreted_options = options_in("interpreter-cache", Backend::interpreted);
    nhc::jit::BuildOptions compiled_options = options_in("interpreter-cache", Backend::compiled);
    interpreted_options.sensitivities = compiled_options.sensitivities = c.sensitivities;
    const nhc::jit::LoadedModel interpreted = nhc::jit::build(scene, c.kind, interpreted_options);
    const nhc::jit::LoadedModel compiled = nhc::jit::build(scene, c.kind, compiled_options);
    REQUIRE(interpreted.timings().interpreted);
    REQUIRE(interpreted.timings().compile == 0.0);
    REQUIRE_FALSE(compiled.timings().interpreted);
    if (c.file == "rolling_disk.toml") REQUIRE(compiled.model().n_speeds() == 3);  // the multiplier-free form
    compare_tables(interpreted.model(), compiled.model(), 5);
    require_close(final_state(interpreted.model(), scene), final_state(compiled.model(), scene), "final state");
  }
}

TEST_CASE("a run that outlasts its compile switches to the compiled model, and the next build is compiled",
          "[jit][interpreter]") {
  const nhc::Scene scene = nhc::parse_scene(kDriven, "driven_pendulum.toml");
  nhc::jit::BuildOptions options = options_in("compile-behind-cache", Backend::automatic);
  fs::remove_all(options.compile.cache_directory);
  options.scene_cache = true;
  options.compile_behind_after = 0.0;  // at the first step: the switch is then sure to happen in this run or after it
  const nhc::jit::LoadedModel first = nhc::jit::build(scene, nhc::ModelKind::chetaev, options);
  REQUIRE(first.timings().interpreted);
  const auto interpreted_residual = first.model().table().residual;
  nhc::jit::CompileBehind behind(scene, nhc::ModelKind::chetaev, options, first);
  using namespace nhc::runtime;
  IntegratorOptions io;
  io.rtol = 1e-10;
  io.atol = 1e-12;
  io.progress = [&](const Progress&) { behind.poll(); };
  const RunResult run = simulate(first.model(), first.model().default_parameters(),
                                 initial_state_from(first.model(), scene.initial.t0, scene.initial.values),
                                 output_times(scene.initial.t0, scene.simulate.t_end, 20), io);
  REQUIRE_FALSE(run.failure);
  REQUIRE(behind.finish());
  REQUIRE(first.model().table().residual != interpreted_residual);  // the compiled function now

  const nhc::jit::LoadedModel second = nhc::jit::build(scene, nhc::ModelKind::chetaev, options);
  REQUIRE_FALSE(second.timings().interpreted);
  REQUIRE(second.timings().scene_cached);
  REQUIRE(second.library().reused);
  // Whether the switch came during the run or after it, the numbers are the compiled model's.
  require_close(run.samples.back().y, final_state(second.model(), scene), "final state after the switch");
}
