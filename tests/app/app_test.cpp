// [app]: the application layer as a unit (app/nhc/app/), called as both front ends call it, each
// result against an answer worked out here by hand: the parameter values a --set gives (and the
// [initial] values written through them), the output times of a run, the sample times of a
// controller, initial values from outside the scene and the initial state they make.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "nhc/app/initial_values.hpp"
#include "nhc/app/optimize_request.hpp"
#include "nhc/app/output_selection.hpp"
#include "nhc/app/parameter_overrides.hpp"
#include "nhc/app/run_request.hpp"
#include "nhc/app/sampled_run.hpp"
#include "nhc/errors.hpp"
#include "nhc/jit.hpp"
#include "nhc/scene/scene.hpp"

namespace {

using nhc::InputError;
using nhc::Scene;

// A particle falling in a plane: m x'' = 0, m y'' = -m g. v and w appear only in [initial], so no
// equation reads them; [simulate] gives t_end but no outputs.
const char* kScene =
    "name = \"falling\"\n"
    "coordinates = [\"x\", \"y\"]\n"
    "lagrangian = \"m/2*(x'^2 + y'^2) - m*g*y\"\n"
    "[parameters]\nm = 1.5\ng = 9.81\nv = 2.0\nw = 4.0\n"
    "[initial]\nt0 = 0.0\nx = [0.0, \"v\"]\ny = [1.0, \"v*w/2\"]\n"
    "[simulate]\nt_end = 2.0\n";

Scene falling() { return nhc::parse_scene(kScene, "falling.toml"); }

double parameter(const Scene& scene, const std::string& name) { return scene.parameter_values_by_name().at(name); }

/// The scene's model, interpreted (nothing compiled) and outside the scene cache.
nhc::jit::LoadedModel interpreted(const Scene& scene) {
  nhc::jit::BuildOptions options;
  options.backend = nhc::jit::Backend::interpreted;
  options.scene_cache = false;
  return nhc::jit::build(scene, nhc::ModelKind::chetaev, options);
}

}  // namespace

TEST_CASE("parameter overrides replace parameters and the initial values written through them", "[app]") {
  Scene scene = falling();
  const std::vector<nhc::app::ParameterOverride> overrides =
      nhc::app::parse_parameter_overrides(scene, {"v=3", "m=2.5", "v=5"});
  nhc::app::apply_parameter_overrides(scene, overrides);
  CHECK(parameter(scene, "v") == 5.0);
  CHECK(parameter(scene, "m") == 2.5);
  CHECK(parameter(scene, "g") == 9.81);  // not given: the scene's
  CHECK(parameter(scene, "w") == 4.0);
  // x' = v and y' = v w / 2 with v = 5, w = 4.
  CHECK(scene.initial.values.at("x").at(1) == 5.0);
  CHECK(scene.initial.values.at("y").at(1) == 10.0);
  CHECK(scene.initial.values.at("y").at(0) == 1.0);
}

TEST_CASE("parameter overrides refuse what is not NAME=NUMBER of a scene parameter", "[app]") {
  const Scene scene = falling();
  for (const std::string bad : {"k=1", "v", "v=", "v=abc", "v=nan", "v=inf", "v=1x", "=2"}) {
    INFO(bad);
    CHECK_THROWS_AS(nhc::app::parse_parameter_overrides(scene, {bad}), InputError);
  }
  const auto [name, value] = nhc::app::split_assignment("--set", "alpha=1e-3");
  CHECK(name == "alpha");
  CHECK(value == "1e-3");
  CHECK(nhc::app::parse_number("--set", "-2.5e2") == -250.0);
}

TEST_CASE("a compiled model's parameters take the overrides it reads at its own indices", "[app]") {
  const Scene scene = falling();
  const nhc::jit::LoadedModel loaded = interpreted(scene);
  const nhc::runtime::Model& model = loaded.model();
  const std::vector<double> defaults = model.default_parameters();
  REQUIRE(model.parameter_index("g") >= 0);
  REQUIRE(model.parameter_index("m") >= 0);
  CHECK(model.parameter_index("v") == -1);  // in no equation: not in the model

  const std::vector<double> p = nhc::app::parameters_with_overrides(model, {{"g", 1.62}, {"v", 7.0}});
  REQUIRE(p.size() == defaults.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const bool is_g = static_cast<int>(i) == model.parameter_index("g");
    CHECK(p[i] == (is_g ? 1.62 : defaults[i]));
  }
  CHECK(defaults[static_cast<std::size_t>(model.parameter_index("m"))] == 1.5);
}

TEST_CASE("output times are equal intervals to t_end or the explicit ones and never collapse", "[app]") {
  const Scene scene = falling();
  const nhc::app::FieldNames& names = nhc::app::command_line_names();

  nhc::app::RunRequest request;
  request.outputs = 4;  // t_end from [simulate]: 2
  const std::vector<double> four = nhc::app::run_output_times(request, scene, names);
  REQUIRE(four.size() == 5);
  for (int k = 0; k <= 4; ++k) CHECK(four[static_cast<std::size_t>(k)] == Approx(0.5 * k).margin(1e-15));
  CHECK(four.back() == 2.0);

  nhc::app::RunRequest shorter;
  shorter.t_end = 1.0;  // outputs from neither the request nor [simulate]: 200 intervals
  const std::vector<double> dflt = nhc::app::run_output_times(shorter, scene, names);
  REQUIRE(dflt.size() == 201);
  CHECK(dflt.front() == 0.0);
  CHECK(dflt[100] == Approx(0.5).margin(1e-15));
  CHECK(dflt.back() == 1.0);

  nhc::app::RunRequest explicit_times;
  explicit_times.output_times = std::vector<double>{0.0, 0.1, 0.7};
  CHECK(nhc::app::run_output_times(explicit_times, scene, names) == std::vector<double>{0.0, 0.1, 0.7});

  // 1000 intervals over 1e-13 at t = 1: each step is below half an ulp of 1 (1.1e-16).
  CHECK_THROWS_AS(nhc::app::equally_spaced_output_times(1.0, 1.0 + 1e-13, 1000, "--outputs"), InputError);
  CHECK(nhc::app::equally_spaced_output_times(1.0, 1.0 + 1e-10, 10, "--outputs").size() == 11);
}

TEST_CASE("output time specifications a:h:b and lists start at t0 and increase", "[app]") {
  const std::vector<double> grid = nhc::app::parse_output_times("0:0.25:1");
  REQUIRE(grid.size() == 5);
  for (int k = 0; k <= 4; ++k) CHECK(grid[static_cast<std::size_t>(k)] == Approx(0.25 * k).margin(1e-15));
  CHECK(nhc::app::parse_output_times("0.5,1.5,4") == std::vector<double>{0.5, 1.5, 4.0});
  for (const std::string bad : {"0:0.3:1", "0.5,0.2", "0:0:1", "1:0.5:0", "a,b", "0,nan"}) {
    INFO(bad);
    CHECK_THROWS_AS(nhc::app::parse_output_times(bad), InputError);
  }
  // Their place against t0 is the run's scene's (a t0 written through a parameter moves with
  // --set): read without it, checked with it.
  const std::vector<double> early = nhc::app::parse_output_times("-1,1");
  CHECK_THROWS_AS(nhc::app::check_output_times(early, 0.0, "--output-times", "-1,1"), InputError);
  CHECK_NOTHROW(nhc::app::check_output_times(early, -1.0, "--output-times", "-1,1"));
  CHECK_THROWS_AS(nhc::app::check_output_times({0.5, 1.0}, 1.0, "--output-times", "0.5,1"), InputError);
}

TEST_CASE("sample times: t0 + k period up to the last at or before t_end", "[app]") {
  const nhc::SourceLocation where{"period", 0, 0};
  // floor((1 - 0)/0.3) = 3: samples 0, 0.3, 0.6, 0.9.
  const std::vector<double> thirds = nhc::app::sample_times(0.0, 1.0, 0.3, where, "period");
  REQUIRE(thirds.size() == 4);
  for (int k = 0; k <= 3; ++k) CHECK(thirds[static_cast<std::size_t>(k)] == Approx(0.3 * k).margin(1e-15));
  // A t_end a whole number of periods away, written in decimals, is the last sample: 2.1/0.7 = 3.
  const std::vector<double> whole = nhc::app::sample_times(0.0, 2.1, 0.7, where, "period");
  REQUIRE(whole.size() == 4);
  CHECK(whole.back() == Approx(2.1).margin(1e-15));
  CHECK(nhc::app::sample_times(5.0, 6.0, 0.5, where, "period") == std::vector<double>{5.0, 5.5, 6.0});
  for (const double bad : {0.0, -0.1, std::nan(""), std::numeric_limits<double>::infinity(), 1.5}) {
    INFO(bad);
    CHECK_THROWS_AS(nhc::app::sample_times(0.0, 1.0, bad, where, "period"), InputError);
  }
}

TEST_CASE("initial values from outside the scene and the initial state they make", "[app]") {
  Scene scene = falling();
  nhc::app::apply_initial_values(scene, {{"x'", 4.0, "x'=4"}, {"y", 3.0, "y=3"}}, "--initial");
  CHECK(scene.initial.values.at("x") == std::vector<double>{0.0, 4.0});
  CHECK(scene.initial.values.at("y").at(0) == 3.0);
  for (const nhc::app::InitialValue& bad :
       std::vector<nhc::app::InitialValue>{{"q", 1.0, "q=1"},
                                           {"x", std::nan(""), "x=nan"},
                                           {"x'''", 1.0, "x'''=1"},  // x'' given neither in the scene nor here
                                           {"x'''''''''", 1.0, "x'''''''''=1"}}) {  // order 9, beyond the limit of 8
    INFO(bad.written);
    Scene copy = falling();
    CHECK_THROWS_AS(nhc::app::apply_initial_values(copy, {bad}, "--initial"), InputError);
  }

  // The state: each coordinate and its derivative at the model's own index, given.
  const nhc::jit::LoadedModel loaded = interpreted(scene);
  const nhc::runtime::Model& model = loaded.model();
  const nhc::runtime::InitialState state = nhc::app::initial_state_of(scene, model);
  CHECK(state.t0 == 0.0);
  const std::map<std::string, std::vector<double>> expected{{"x", {0.0, 4.0}}, {"y", {3.0, 4.0}}};
  for (int j = 0; j < 2; ++j) {
    const std::string name = model.variable_name(j);
    INFO(name);
    for (int order = 0; order < 2; ++order) {
      const int i = model.state_index(j, order);
      REQUIRE(i >= 0);
      CHECK(state.y[static_cast<std::size_t>(i)] == expected.at(name)[static_cast<std::size_t>(order)]);
      CHECK(state.given[static_cast<std::size_t>(i)]);
    }
  }
}

TEST_CASE("a new t0 moves the default end of the run with it", "[app]") {
  // Without [simulate] t_end a run ends at t0 + 1.
  Scene scene = nhc::parse_scene(
      "name = \"free\"\ncoordinates = [\"x\"]\nlagrangian = \"x'^2/2\"\n[initial]\nt0 = 0.0\nx = [0.0, 1.0]\n",
      "free.toml");
  CHECK(nhc::app::run_t_end(scene, std::nullopt, "--t-end") == 1.0);
  nhc::app::apply_initial_values(scene, {{"t0", 2.5, "t0=2.5"}}, "--initial");
  CHECK(scene.initial.t0 == 2.5);
  CHECK(nhc::app::run_t_end(scene, std::nullopt, "--t-end") == 3.5);
  CHECK(nhc::app::run_t_end(scene, 10.0, "--t-end") == 10.0);
  CHECK_THROWS_AS(nhc::app::run_t_end(scene, 2.0, "--t-end"), InputError);  // before t0

  // With [simulate] t_end, a t0 past it is refused where the run's end is asked for.
  Scene fixed_end = falling();
  nhc::app::apply_initial_values(fixed_end, {{"t0", 3.0, "t0=3"}}, "--initial");
  CHECK_THROWS_AS(nhc::app::run_t_end(fixed_end, std::nullopt, "--t-end"), InputError);
}

TEST_CASE("an optimize request's solver choices: by name from the front ends, typed for the solver", "[app]") {
  nhc::app::OptimizeRequest request;
  CHECK(nhc::app::optimize_choices(request).jacobian == nhc::app::JacobianChoice::exact);
  CHECK(nhc::app::optimize_choices(request).hessian == nhc::app::HessianChoice::exact);
  request.jacobian = "finite-differences";
  request.hessian = "limited-memory";
  request.max_iterations = 17;
  request.tolerance = 1e-7;
  request.path_tolerance = 1e-4;
  nhc::app::check_optimize_request(request, nhc::app::optimize_python_names());
  const nhc::app::OptimizeChoices choices = nhc::app::optimize_choices(request);
  CHECK(choices.jacobian == nhc::app::JacobianChoice::finite_differences);
  CHECK(choices.hessian == nhc::app::HessianChoice::limited_memory);
  CHECK(choices.max_iterations == 17);
  CHECK(choices.tolerance == 1e-7);
  CHECK(choices.path_tolerance == 1e-4);
  request.hessian = "bfgs";
  CHECK_THROWS_WITH(nhc::app::check_optimize_request(request, nhc::app::optimize_command_line_names()),
                    "--hessian: error: --hessian: 'bfgs' is neither exact nor limited-memory");
}
