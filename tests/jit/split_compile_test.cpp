// [jit][split]: a generated header compiled as several translation units (NHC_PART of NHC_PARTS,
// linked into one library) is the same model as the header compiled as one: every function of
// the table gives the same numbers at random points, for 2, 3 and 4 parts, dense and sparse
// Jacobians. The reference is the single translation unit, i.e. the code applications compile
// through nhc_add_model; the split changes only which object each function lives in.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "nhc/jit.hpp"
#include "nhc/scene/scene_builder.hpp"

namespace fs = std::filesystem;

namespace {

/// Three knife edges joined by springs on an incline (bench/knife_chain.py, N = 3), with an
/// invariant, so that the header has every kind of function: residual, Jacobian, hidden
/// constraints and their Jacobian, invariants.
nhc::Scene knife_chain() {
  nhc::SceneBuilder b("split_chain");
  b.coordinates({"x1", "y1", "th1", "x2", "y2", "th2", "x3", "y3", "th3"});
  for (const auto& [name, value] : std::vector<std::pair<std::string, double>>{
           {"m", 1.0}, {"J", 0.1}, {"g", 9.81}, {"alpha", 0.3}, {"k", 10.0}, {"l", 1.0}})
    b.parameter(name, value);
  std::string lagrangian, energy;
  for (int i = 1; i <= 3; ++i) {
    const std::string s = std::to_string(i);
    lagrangian += (i > 1 ? "+" : "") + ("m/2*(x" + s + "'^2+y" + s + "'^2)+J/2*th" + s + "'^2+m*g*sin(alpha)*x" + s);
    energy += (i > 1 ? "+" : "") + ("m/2*(x" + s + "'^2+y" + s + "'^2)+J/2*th" + s + "'^2-m*g*sin(alpha)*x" + s);
    b.constraint("x" + s + "'*sin(th" + s + ") - y" + s + "'*cos(th" + s + ")");
    b.initial("x" + s, {0.1 * i, 1.0}).initial("y" + s, {1.0 * i}).initial("th" + s, {0.2 * i, 0.5});
  }
  for (int i = 1; i < 3; ++i) {
    const std::string s = std::to_string(i), t = std::to_string(i + 1);
    const std::string spring = "k/2*((x" + t + "-x" + s + ")^2+(y" + t + "-y" + s + "-l)^2)";
    lagrangian += "-" + spring;
    energy += "+" + spring;
  }
  return b.lagrangian(lagrangian).invariant("E", energy).build();
}

/// Every function of the table evaluated at one point (t, y, yp, cj, p drawn from `u`), all
/// outputs in one list; absent functions contribute nothing.
std::vector<double> evaluate_all(const nhc_model_table& t, std::mt19937& random) {
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  const auto n = static_cast<std::size_t>(t.n_states);
  std::vector<double> y(n), yp(n), p(static_cast<std::size_t>(std::max(1, t.n_parameters)));
  for (double& v : y) v = u(random);
  for (double& v : yp) v = u(random);
  for (double& v : p) v = u(random);
  const double time = u(random), cj = 10 + u(random);
  std::vector<double> all, out;
  auto append = [&] { all.insert(all.end(), out.begin(), out.end()); };
  out.assign(n, 0.0);
  t.residual(time, y.data(), yp.data(), p.data(), out.data());
  append();
  if (t.jacobian) {
    out.assign(n * n, 0.0);
    t.jacobian(time, y.data(), yp.data(), cj, p.data(), out.data());
    append();
  }
  if (t.jacobian_values) {
    out.assign(static_cast<std::size_t>(t.jacobian_nnz), 0.0);
    t.jacobian_values(time, y.data(), yp.data(), cj, p.data(), out.data());
    append();
  }
  const auto hidden = static_cast<std::size_t>(t.n_hidden);
  if (t.hidden_constraints) {
    out.assign(hidden, 0.0);
    t.hidden_constraints(time, y.data(), p.data(), out.data());
    append();
    out.assign(hidden * n, 0.0);
    t.hidden_constraints_jacobian(time, y.data(), p.data(), out.data());
    append();
  }
  if (t.invariants) {
    out.assign(static_cast<std::size_t>(t.n_invariants), 0.0);
    t.invariants(time, y.data(), yp.data(), p.data(), out.data());
    append();
  }
  return all;
}

}  // namespace

TEST_CASE("a header compiled as 2, 3 or 4 translation units gives the numbers of one", "[jit][split]") {
  const fs::path cache = fs::path(NHC_BINARY_DIR) / "tests" / "jit" / "split-cache";
  fs::remove_all(cache);
  const nhc::Scene scene = knife_chain();
  for (const nhc::JacobianKind jacobian : {nhc::JacobianKind::dense, nhc::JacobianKind::sparse}) {
    nhc::jit::BuildOptions options;
    options.jacobian = jacobian;
    options.split_from_bytes = 0;  // a small chain, split on purpose
    options.compile.cache_directory = cache;
    options.compile.translation_units = 1;
    const nhc::jit::LoadedModel one = nhc::jit::build(scene, nhc::ModelKind::chetaev, options);
    REQUIRE(one.library().translation_units == 1);
    REQUIRE(one.model().table().invariants != nullptr);
    REQUIRE(one.model().table().hidden_constraints != nullptr);
    for (int parts = 2; parts <= 4; ++parts) {
      INFO(nhc::to_string(jacobian) << " Jacobian, " << parts << " translation units");
      options.compile.translation_units = parts;
      const nhc::jit::LoadedModel split = nhc::jit::build(scene, nhc::ModelKind::chetaev, options);
      CHECK(split.library().translation_units == parts);
      CHECK_FALSE(split.library().reused);
      CHECK(split.library().path != one.library().path);  // the cache key covers the split
      REQUIRE(&split.model().table() != &one.model().table());
      const nhc_model_table& a = one.model().table();
      const nhc_model_table& b = split.model().table();
      // Every function present in one is present in the other.
      CHECK(!a.jacobian == !b.jacobian);
      CHECK(!a.jacobian_values == !b.jacobian_values);
      CHECK(!a.hidden_constraints_jacobian == !b.hidden_constraints_jacobian);
      CHECK(!a.invariants == !b.invariants);
      CHECK(b.n_states == a.n_states);
      std::mt19937 random_a(17 + parts), random_b(17 + parts);
      for (int point = 0; point < 20; ++point) {
        const std::vector<double> x = evaluate_all(a, random_a), z = evaluate_all(b, random_b);
        REQUIRE(x.size() == z.size());
        for (std::size_t i = 0; i < x.size(); ++i) {
          INFO("output " << i << " at point " << point);
          CHECK(z[i] == Approx(x[i]).epsilon(1e-13).margin(1e-13));
        }
      }
    }
  }
}

TEST_CASE("a header without the split banner is compiled as one translation unit", "[jit][split]") {
  nhc::jit::CompileOptions options;
  options.cache_directory = fs::path(NHC_BINARY_DIR) / "tests" / "jit" / "split-handwritten-cache";
  fs::remove_all(options.cache_directory);
  options.translation_units = 3;
  const nhc::jit::CompiledLibrary library = nhc::jit::compile_header_file(
      fs::path(NHC_SOURCE_DIR) / "tests/runtime/handwritten/appell_hamel_chetaev.hpp", options);
  CHECK(library.translation_units == 1);
}

TEST_CASE("a long header is compiled at -O0 in place of the -O flags, the others as given", "[jit][split]") {
  nhc::jit::CompileOptions options;
  options.flags = {"-O2", "-g0", "-O3"};
  options.long_header_bytes = 1000;
  CHECK(nhc::jit::optimization_flags(options, 1000) == options.flags);
  CHECK(nhc::jit::optimization_flags(options, 1001) == std::vector<std::string>{"-O0", "-g0"});
  options.long_header_bytes = 0;  // the flags as given
  CHECK(nhc::jit::optimization_flags(options, 100000000) == options.flags);
}

TEST_CASE("a header compiled at -O0 gives the numbers of the one compiled at -O2", "[jit][split]") {
  const fs::path cache = fs::path(NHC_BINARY_DIR) / "tests" / "jit" / "level-cache";
  fs::remove_all(cache);
  const nhc::Scene scene = knife_chain();
  nhc::jit::BuildOptions options;
  options.backend = nhc::jit::Backend::compiled;
  options.scene_cache = false;
  options.compile.cache_directory = cache;
  options.compile.long_header_bytes = 0;  // -O2, as given
  const nhc::jit::LoadedModel optimized = nhc::jit::build(scene, nhc::ModelKind::chetaev, options);
  options.compile.long_header_bytes = 1;  // every header long: -O0
  const nhc::jit::LoadedModel quick = nhc::jit::build(scene, nhc::ModelKind::chetaev, options);
  CHECK(quick.library().path != optimized.library().path);  // the cache key covers the level
  REQUIRE(&quick.model().table() != &optimized.model().table());
  std::mt19937 random_a(5), random_b(5);
  for (int point = 0; point < 20; ++point) {
    const std::vector<double> x = evaluate_all(optimized.model().table(), random_a);
    const std::vector<double> z = evaluate_all(quick.model().table(), random_b);
    REQUIRE(x.size() == z.size());
    for (std::size_t i = 0; i < x.size(); ++i) {
      INFO("output " << i << " at point " << point);
      CHECK(z[i] == Approx(x[i]).epsilon(1e-13).margin(1e-13));
    }
  }
}
