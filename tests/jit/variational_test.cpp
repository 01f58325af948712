// The variational integrator (docs/variational.md) against closed forms and conserved quantities:
// - the knife edge turning uniformly: x = (v/w) sin(wt), y = (v/w)(1 - cos(wt)), phi = wt;
// - the Chaplygin sleigh without friction (docs/variational.md derives it): with I = J + m a^2 and
//   V^2 = v0^2 + (I/m) w0^2, the speed along the blade v = V tanh(s), s = (a m V/I) t + c,
//   tanh(c) = v0/V, the turning rate w = w0 cosh(c) sech(s), th = th0 + w0 cosh(c) I/(a m V) (gd(s) - gd(c)),
//   gd(s) = atan(sinh(s));
// - the particle on a circle (a holonomic constraint): uniform circular motion and its multiplier;
// the observed order of convergence is the midpoint rule's 2; the discrete constraints hold to
// rounding; the energy error of the rolling ball, the rolling disk and the sleigh stays bounded
// over 100 times as many steps while IDA's grows (where the motion does not settle).
#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "nhc/jit.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"

namespace fs = std::filesystem;
namespace rt = nhc::runtime;

namespace {

nhc::jit::LoadedModel build_variational(const nhc::Scene& scene) {
  nhc::jit::BuildOptions options;
  options.variational = true;
  options.compile.cache_directory = fs::path(NHC_BINARY_DIR) / "tests" / "jit" / "variational-cache";
  return nhc::jit::build(scene, nhc::ModelKind::chetaev, options);
}

rt::VariationalRun run(const rt::Model& model, const std::vector<double>& p, const nhc::Scene& scene, double h,
                       double t_end, int outputs, const rt::InputFunction& inputs = {}) {
  rt::VariationalOptions options;
  options.step = h;
  options.max_steps = 10000000;
  options.initialization.rtol = 1e-12;
  options.initialization.atol = 1e-14;
  return rt::simulate_variational(model, p, rt::initial_state_from(model, scene.initial.t0, scene.initial.values),
                                  rt::output_times(scene.initial.t0, t_end, outputs), options, inputs);
}

/// max over the samples of |state - exact(t)|, for the states `exact` gives (NaN: not compared).
double max_error(const rt::Model& model, const rt::RunResult& result,
                 const std::function<std::vector<double>(double)>& exact) {
  double worst = 0;
  for (const rt::Sample& s : result.samples) {
    const std::vector<double> e = exact(s.t);
    for (int i = 0; i < model.n_states(); ++i)
      if (!std::isnan(e[static_cast<std::size_t>(i)]))
        worst = std::max(worst, std::abs(s.y[static_cast<std::size_t>(i)] - e[static_cast<std::size_t>(i)]));
  }
  return worst;
}

/// The errors at steps h, h/2, h/4 and the orders log2(e(h)/e(h/2)) between them.
std::vector<double> observed_orders(const std::vector<double>& errors) {
  std::vector<double> orders;
  for (std::size_t k = 1; k < errors.size(); ++k) orders.push_back(std::log2(errors[k - 1] / errors[k]));
  return orders;
}

std::vector<double> exact_by_state(const rt::Model& model, const std::vector<std::pair<std::string, double>>& values) {
  std::vector<double> out(static_cast<std::size_t>(model.n_states()), std::nan(""));
  for (const auto& [name, value] : values)
    for (int i = 0; i < model.n_states(); ++i)
      if (model.state_name(i) == name) out[static_cast<std::size_t>(i)] = value;
  return out;
}

const char* kKnifeEdge = R"toml(name = "knife_edge_turning"
coordinates = ["x", "y", "phi"]
lagrangian = "m/2*(x'^2 + y'^2) + J/2*phi'^2"
constraints = ["x'*sin(phi) - y'*cos(phi)"]
[parameters]
m = 1.0
J = 0.5
[initial]
x = [0.0, 1.0]
y = [0.0, 0.0]
phi = [0.0, 2.0]
)toml";

const char* kSleigh = R"toml(name = "sleigh_free"
coordinates = ["x", "y", "th"]
lagrangian = "m/2*dot(G', G') + J/2*th'^2"
constraints = ["dot(e2, p')"]
[definitions]
p  = "[x, y]"
e1 = "[cos(th), sin(th)]"
e2 = "[-sin(th), cos(th)]"
G  = "p + a*e1"
[parameters]
m = 1.0
J = 0.2
a = 0.3
[initial]
x = [0.0, 1.0]
y = [0.0, 0.0]
th = [0.0, 1.5]
[invariants]
energy = "m/2*dot(G', G') + J/2*th'^2"
)toml";

}  // namespace

TEST_CASE("variational: the knife edge converges with order 2 to its closed form, constraints at rounding",
          "[jit][variational]") {
  const nhc::Scene scene = nhc::parse_scene(kKnifeEdge, "knife_edge_turning.toml");
  const nhc::jit::LoadedModel built = build_variational(scene);
  const rt::Model& model = built.model();
  REQUIRE(model.has_variational_step());
  const double v = 1.0, w = 2.0;
  const auto exact = [&](double t) {
    return exact_by_state(model, {{"x", v / w * std::sin(w * t)},
                                  {"y", v / w * (1 - std::cos(w * t))},
                                  {"phi", w * t},
                                  {"x'", v * std::cos(w * t)},
                                  {"y'", v * std::sin(w * t)},
                                  {"phi'", w}});
  };
  std::vector<double> errors;
  for (double h : {0.05, 0.025, 0.0125}) {
    const rt::VariationalRun r = run(model, {}, scene, h, 5.0, 50);
    REQUIRE_FALSE(r.run.failure);
    REQUIRE(r.run.samples.size() == 51);
    CHECK(r.max_discrete_constraint < 1e-13);
    errors.push_back(max_error(model, r.run, exact));
  }
  INFO("errors " << errors[0] << " " << errors[1] << " " << errors[2]);
  for (double order : observed_orders(errors)) CHECK(order == Approx(2.0).margin(0.1));
  CHECK(errors[2] < 1e-3);
}

TEST_CASE("variational: the frictionless Chaplygin sleigh converges with order 2 to its closed form",
          "[jit][variational]") {
  const nhc::Scene scene = nhc::parse_scene(kSleigh, "sleigh_free.toml");
  const nhc::jit::LoadedModel built = build_variational(scene);
  const rt::Model& model = built.model();
  const double m = 1.0, J = 0.2, a = 0.3, v0 = 1.0, w0 = 1.5;
  const double I = J + m * a * a, V = std::sqrt(v0 * v0 + I / m * w0 * w0), c = std::atanh(v0 / V);
  const double rate = a * m * V / I, C = w0 * std::cosh(c);
  const auto gd = [](double s) { return std::atan(std::sinh(s)); };
  const auto exact = [&](double t) {
    const double s = rate * t + c;
    return exact_by_state(model, {{"th", C / rate * (gd(s) - gd(c))}, {"th'", C / std::cosh(s)}});
  };
  std::vector<double> errors, speed_errors;
  for (double h : {0.04, 0.02, 0.01}) {
    const rt::VariationalRun r = run(model, {}, scene, h, 8.0, 40);
    REQUIRE_FALSE(r.run.failure);
    CHECK(r.max_discrete_constraint < 1e-12);
    errors.push_back(max_error(model, r.run, exact));
    // The speed along the blade, v = x' cos th + y' sin th, from the states.
    double worst = 0;
    const int x = model.state_index(0, 1), y = model.state_index(1, 1), th = model.state_index(2, 0);
    for (const rt::Sample& s : r.run.samples) {
      const double along = s.y[x] * std::cos(s.y[th]) + s.y[y] * std::sin(s.y[th]);
      worst = std::max(worst, std::abs(along - V * std::tanh(rate * s.t + c)));
    }
    speed_errors.push_back(worst);
  }
  INFO("th, th' errors " << errors[0] << " " << errors[1] << " " << errors[2] << "; speed errors " << speed_errors[0]
                         << " " << speed_errors[1] << " " << speed_errors[2]);
  for (double order : observed_orders(errors)) CHECK(order == Approx(2.0).margin(0.15));
  for (double order : observed_orders(speed_errors)) CHECK(order == Approx(2.0).margin(0.15));
}

TEST_CASE("variational: a holonomic constraint, the particle on a circle, order 2 and the multiplier",
          "[jit][variational]") {
  // L = m/2 (x'² + y'²), x² + y² = R² (order 0: imposed at the nodes), speed v: x = R cos(wt),
  // y = R sin(wt), w = v/R; the chetaev residual −m q'' + 2 λ q = 0 gives λ = −m w²/2.
  const nhc::Scene scene = nhc::parse_scene(R"toml(name = "ring"
coordinates = ["x", "y"]
lagrangian = "m/2*(x'^2 + y'^2)"
constraints = ["x^2 + y^2 - R^2"]
[parameters]
m = 1.0
R = 2.0
[initial]
x = [2.0, 0.0]
y = [0.0, 3.0]
)toml",
                                            "ring.toml");
  const nhc::jit::LoadedModel built = build_variational(scene);
  const rt::Model& model = built.model();
  const double R = 2.0, w = 1.5, m = 1.0;
  const auto exact = [&](double t) {
    return exact_by_state(model, {{"x", R * std::cos(w * t)},
                                  {"y", R * std::sin(w * t)},
                                  {"x'", -R * w * std::sin(w * t)},
                                  {"y'", R * w * std::cos(w * t)},
                                  {"lambda1", -m * w * w / 2}});
  };
  std::vector<double> errors;
  for (double h : {0.02, 0.01, 0.005}) {
    const rt::VariationalRun r = run(model, {}, scene, h, 4.0, 40);
    REQUIRE_FALSE(r.run.failure);
    CHECK(r.max_discrete_constraint < 1e-13);
    errors.push_back(max_error(model, r.run, exact));
  }
  INFO("errors " << errors[0] << " " << errors[1] << " " << errors[2]);
  for (double order : observed_orders(errors)) CHECK(order == Approx(2.0).margin(0.1));
}

namespace {

/// max |E(t) − E(t0)| of the scene's invariant `energy` over the samples.
double energy_error(const rt::Model& model, const std::vector<double>& p, const rt::RunResult& result) {
  const rt::DriftReport drift = rt::measure_drift(model, p, result.samples);
  for (int k = 0; k < model.n_invariants(); ++k)
    if (std::string(model.table().invariant_names[k]) == "energy")
      return drift.invariant_drift[static_cast<std::size_t>(k)];
  FAIL("no invariant named energy");
  return 0;
}

}  // namespace

TEST_CASE("variational: the energy error stays bounded over 100 times the steps, IDA's grows", "[jit][variational]") {
  struct Case {
    std::string name;
    nhc::Scene scene;
    /// IDA's error grows along the run: not on the sleigh, whose motion tends to a straight line
    /// at constant speed (the closed form above), where IDA's steps add no more error.
    bool ida_grows;
  };
  std::vector<Case> cases;
  const fs::path examples = fs::path(NHC_SOURCE_DIR) / "examples";
  cases.push_back({"rolling ball", nhc::load_scene((examples / "rolling_ball.toml").string()), true});
  // The disk wobbling about upright rolling (the example's steady circle lies near a separatrix,
  // where a fixed step meets fast phases: docs/variational.md).
  cases.push_back(
      {"rolling disk",
       nhc::load_scene((fs::path(NHC_SOURCE_DIR) / "bench" / "variational" / "rolling_disk_wobble.toml").string()),
       true});
  cases.push_back({"sleigh", nhc::parse_scene(kSleigh, "sleigh_free.toml"), false});
  const double h = 0.02;
  const long short_steps = 500, long_steps = 50000;
  for (const Case& c : cases) {
    const nhc::jit::LoadedModel built = build_variational(c.scene);
    const rt::Model& model = built.model();
    const std::vector<double> p = model.default_parameters();
    const double t0 = c.scene.initial.t0;
    const rt::VariationalRun brief = run(model, p, c.scene, h, t0 + h * short_steps, 500);
    const rt::VariationalRun lasting = run(model, p, c.scene, h, t0 + h * long_steps, 5000);
    REQUIRE_FALSE(brief.run.failure);
    REQUIRE_FALSE(lasting.run.failure);
    const double e_short = energy_error(model, p, brief.run), e_long = energy_error(model, p, lasting.run);
    // IDA at a loose tolerance over the same spans: its error accumulates.
    rt::IntegratorOptions io;
    io.rtol = 1e-6;
    io.atol = 1e-8;
    const rt::InitialState initial = rt::initial_state_from(model, t0, c.scene.initial.values);
    const rt::RunResult ida_short =
        rt::simulate(model, p, initial, rt::output_times(t0, t0 + h * short_steps, 500), io);
    const rt::RunResult ida_long = rt::simulate(model, p, initial, rt::output_times(t0, t0 + h * long_steps, 5000), io);
    const double i_short = energy_error(model, p, ida_short), i_long = energy_error(model, p, ida_long);
    INFO(c.name << ": variational " << e_short << " over " << short_steps << " steps, " << e_long << " over "
                << long_steps << "; IDA " << i_short << ", " << i_long);
    CHECK(e_long <= 3 * e_short);
    if (c.ida_grows) CHECK(i_long >= 10 * i_short);
  }
}

TEST_CASE("variational: a feedback input, the knife edge's turning damped by u = -c phi', order 2",
          "[jit][variational]") {
  // J phi'' = u = −c phi' (the input as the force on phi, set by the run as a function of the
  // state): phi' = w0 e^(−c t/J), phi = (J w0/c)(1 − e^(−c t/J)); the constraint force does no
  // work along the blade, so the speed there stays v0.
  const nhc::Scene scene = nhc::parse_scene(std::string(kKnifeEdge) + "[inputs]\nu = \"0\"\n[forces]\nphi = \"u\"\n",
                                            "knife_edge_damped.toml");
  const nhc::jit::LoadedModel built = build_variational(scene);
  const rt::Model& model = built.model();
  REQUIRE(model.n_inputs() == 1);
  const double J = 0.5, w0 = 2.0, c = 0.8, v0 = 1.0;
  const int phi_rate = model.state_index(2, 1);
  const rt::InputFunction damping = [&](double, const double* y, double* u) { u[0] = -c * y[phi_rate]; };
  const auto exact = [&](double t) {
    const double decay = std::exp(-c * t / J);
    return exact_by_state(model, {{"phi", J * w0 / c * (1 - decay)}, {"phi'", w0 * decay}});
  };
  std::vector<double> errors;
  for (double h : {0.02, 0.01, 0.005}) {
    const rt::VariationalRun r = run(model, {}, scene, h, 3.0, 30, damping);
    REQUIRE_FALSE(r.run.failure);
    errors.push_back(max_error(model, r.run, exact));
    const int xd = model.state_index(0, 1), yd = model.state_index(1, 1);
    for (const rt::Sample& s : r.run.samples)
      CHECK(std::hypot(s.y[static_cast<std::size_t>(xd)], s.y[static_cast<std::size_t>(yd)]) ==
            Approx(v0).margin(4 * h * h));
  }
  INFO("errors " << errors[0] << " " << errors[1] << " " << errors[2]);
  CHECK(errors[2] < 1e-4);
  for (double order : observed_orders(errors)) CHECK(order == Approx(2.0).margin(0.15));
}

TEST_CASE(
    "variational: a step that does not divide the run ends on t_end, order 2 kept; one that does not fit twice is "
    "refused",
    "[jit][variational]") {
  const nhc::Scene scene = nhc::parse_scene(kKnifeEdge, "knife_edge_turning.toml");
  const nhc::jit::LoadedModel built = build_variational(scene);
  const rt::Model& model = built.model();
  const double v = 1.0, w = 2.0;
  const auto exact = [&](double t) {
    return exact_by_state(model, {{"x", v / w * std::sin(w * t)},
                                  {"y", v / w * (1 - std::cos(w * t))},
                                  {"phi", w * t},
                                  {"x'", v * std::cos(w * t)},
                                  {"y'", v * std::sin(w * t)},
                                  {"phi'", w}});
  };
  // 5/0.03 = 166.7: 167 steps of 5/167, the last node t_end = 5 with its backward-difference velocity.
  std::vector<double> errors, last_errors;
  for (double h : {0.03, 0.015, 0.0075}) {
    const rt::VariationalRun r = run(model, {}, scene, h, 5.0, 7);
    REQUIRE_FALSE(r.run.failure);
    REQUIRE(r.run.samples.size() == 8);
    CHECK(r.run.samples.back().t == 5.0);
    CHECK(r.steps == static_cast<long>(std::ceil(5.0 / h)));
    errors.push_back(max_error(model, r.run, exact));
    rt::RunResult last;
    last.samples = {r.run.samples.back()};
    last_errors.push_back(max_error(model, last, exact));
  }
  INFO("errors " << errors[0] << " " << errors[1] << " " << errors[2] << ", at t_end " << last_errors[0] << " "
                 << last_errors[1] << " " << last_errors[2]);
  for (double order : observed_orders(errors)) CHECK(order == Approx(2.0).margin(0.1));
  for (double order : observed_orders(last_errors)) CHECK(order == Approx(2.0).margin(0.1));
  // A step that fits the run less than twice: refused before anything is solved.
  CHECK_THROWS_AS(run(model, {}, scene, 2.6, 5.0, 2), std::invalid_argument);
  CHECK_FALSE(run(model, {}, scene, 2.5, 5.0, 2).run.failure);
}
