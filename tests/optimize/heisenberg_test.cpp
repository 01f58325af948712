// nhc::optimize against the closed form of the Heisenberg (Brockett) system (docs/optimize.md):
// from (0, 0, 0) to (0, 0, a) in time T the least 1/2 int (x'^2 + y'^2) dt is 2 pi a / T, on a
// circle of radius sqrt(a/pi) through the origin, run at constant speed.
#include <catch2/catch.hpp>

#include <fmt/format.h>

#include <cmath>

#include "nhc/optimize/hermite_simpson.hpp"
#include "nhc/optimize/settings.hpp"
#include "nhc/optimize/solve.hpp"
#include "nhc/scene/scene.hpp"

using namespace nhc;

namespace {

std::string heisenberg(double a, double t_end, const std::string& bounds = "") {
  return fmt::format(R"TOML(name = "heisenberg"
coordinates = ["x", "y", "z"]
lagrangian = "1/2*(x'^2 + y'^2)"
constraints = ["z' - (x*y' - y*x')/2"]
models = ["vakonomic"]
[optimize]
t_end = {}
[optimize.initial]
x = 0.0
y = 0.0
z = 0.0
[optimize.final]
x = 0.0
y = 0.0
z = {}
{})TOML",
                     t_end, a, bounds.empty() ? "" : "[optimize.bounds]\n" + bounds);
}

struct Optimum {
  optimize::Solution solution;
  std::vector<double> x, y, xp, yp;  // at the 2N + 1 collocation points
};

Optimum solve(const std::string& text, int intervals) {
  const Scene scene = parse_scene(text, "heisenberg.toml");
  const optimize::Settings settings = optimize::read_settings(scene);
  optimize::HermiteSimpson problem(scene, settings, intervals);
  Optimum out;
  out.solution = optimize::solve(problem, problem.straight_line());
  for (int j = 0; j < problem.points(); ++j) {
    out.x.push_back(out.solution.z[static_cast<std::size_t>(problem.q_index(j, 0))]);
    out.y.push_back(out.solution.z[static_cast<std::size_t>(problem.q_index(j, 1))]);
    out.xp.push_back(out.solution.z[static_cast<std::size_t>(problem.v_index(j, 0))]);
    out.yp.push_back(out.solution.z[static_cast<std::size_t>(problem.v_index(j, 1))]);
  }
  return out;
}

}  // namespace

TEST_CASE("the Heisenberg system's optimal loop is the isoperimetric circle", "[optimize]") {
  for (const auto& [a, t_end] : {std::pair{0.5, 1.0}, std::pair{2.0, 3.0}}) {
    INFO("a = " << a << ", T = " << t_end);
    const Optimum o = solve(heisenberg(a, t_end), 50);
    REQUIRE(o.solution.status == optimize::Solution::Status::optimal);
    CHECK(o.solution.violation < 1e-9);
    const double cost = 2 * M_PI * a / t_end;
    CHECK(std::abs(o.solution.cost - cost) < 1e-6 * cost);

    // The points are equally spaced in t on a loop run at constant speed: their mean over one
    // period (the last point repeats the first) is the centre.
    const std::size_t period = o.x.size() - 1;
    double cx = 0, cy = 0;
    for (std::size_t j = 0; j < period; ++j) cx += o.x[j] / period, cy += o.y[j] / period;
    const double r = std::sqrt(a / M_PI), speed = 2 * M_PI * r / t_end;
    CHECK(std::abs(std::hypot(cx, cy) - r) < 1e-4 * r);  // through the origin
    double radius_error = 0, speed_error = 0;
    for (std::size_t j = 0; j < o.x.size(); ++j) {
      radius_error = std::max(radius_error, std::abs(std::hypot(o.x[j] - cx, o.y[j] - cy) - r));
      speed_error = std::max(speed_error, std::abs(std::hypot(o.xp[j], o.yp[j]) - speed));
    }
    CHECK(radius_error < 1e-4 * r);
    // The rates, Hermite-Simpson's controls, are second order at the points (6.6e-4 at 50
    // intervals, 1.6e-4 at 100: docs/optimize.md, "Accuracy").
    CHECK(speed_error < 1e-3 * speed);
  }
}

TEST_CASE("the cost converges at the fourth order of Hermite-Simpson", "[optimize]") {
  const double exact = 2 * M_PI * 0.5;
  const double coarse = std::abs(solve(heisenberg(0.5, 1.0), 10).solution.cost - exact);
  const double fine = std::abs(solve(heisenberg(0.5, 1.0), 20).solution.cost - exact);
  INFO("errors " << coarse << " at 10 intervals, " << fine << " at 20");
  CHECK(std::log2(coarse / fine) > 3.8);
  CHECK(std::log2(coarse / fine) < 4.2);
}

TEST_CASE("bounds hold along the optimal path and can only raise the cost", "[optimize]") {
  // The free optimum's circle spans 2 sqrt(a/pi) = 0.80 in some direction; |x| <= 0.3 and
  // |y'| <= 2.5 (its speed is 2 pi r / T = 2.51) cut it.
  const Optimum o = solve(heisenberg(0.5, 1.0, "x = [-0.3, 0.3]\n\"y'\" = [-2.5, 2.5]\n"), 40);
  REQUIRE(o.solution.status == optimize::Solution::Status::optimal);
  for (std::size_t j = 0; j < o.x.size(); ++j) {
    CHECK(std::abs(o.x[j]) <= 0.3);
    CHECK(std::abs(o.yp[j]) <= 2.5);
  }
  CHECK(o.solution.cost > 2 * M_PI * 0.5 * (1 + 1e-3));
}

TEST_CASE("[optimize] entries are located in the scene", "[optimize]") {
  auto message = [](const std::string& text) {
    try {
      const Scene scene = parse_scene(text, "heisenberg.toml");
      optimize::read_settings(scene);
      optimize::HermiteSimpson(scene, optimize::read_settings(scene), 10);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(message(heisenberg(0.5, 1.0, "q = [0, 1]\n")) ==
        "heisenberg.toml:17:1: error: unknown name 'q' (coordinates with primes for derivatives: x, y, z)");
  CHECK(message(heisenberg(0.5, 1.0, "z = [0, 0.4]\n")) ==
        "heisenberg.toml:15:1: error: z = 0.5 in [optimize.final] is outside its bound [0, 0.4] in [optimize.bounds]");
  CHECK(message(heisenberg(0.5, 1.0, "x = [1, 0]\n")) ==
        "heisenberg.toml:17:5: error: the low bound of x is above its high bound");
  CHECK(message(heisenberg(0.5, 0.0)) == "heisenberg.toml:7:9: error: t_end must be after t0 = 0");
  CHECK(message(heisenberg(0.5, 1.0, "\"x''\" = [0, 1]\n")) ==
        "heisenberg.toml:17:1: error: 'x''': without [inputs] the transcription holds coordinates and their first "
        "derivatives only");
}

TEST_CASE("[optimize] is read with the scene: its keys escaped, its numbers at the parameters' values of the time",
          "[optimize]") {
  auto load_message = [](const std::string& text) {
    try {
      parse_scene(text, "heisenberg.toml");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  // The loader refuses an unknown key of [optimize] at its place, the key's control character escaped.
  std::string text = heisenberg(0.5, 1.0);
  text.replace(text.find("t_end = 1"), 9, "\"k\\u0001\" = 1\nt_end = 1");
  CHECK(load_message(text) ==
        "heisenberg.toml:7:1: error: unknown key 'k\\x01' in [optimize] (expected one of: bounds, final, final_cost, "
        "initial, intervals, model, objective, t_end)");
  // A number given through a parameter follows a value set after the file was read.
  text = heisenberg(0.5, 1.0);
  text.replace(text.rfind("z = 0.5"), 7, "z = \"a\"\n[parameters]\na = 0.5");
  Scene scene = parse_scene(text, "heisenberg.toml");
  REQUIRE(scene.optimize.present);
  CHECK(optimize::read_settings(scene).final.at(2).low == 0.5);
  scene.parameter_values.at(0) = 0.25;
  CHECK(optimize::read_settings(scene).final.at(2).low == 0.25);
  CHECK(optimize::read_settings(scene).final.at(2).high == 0.25);
  // A scene without the table: refused by nhc optimize at the file, not by the loader.
  const Scene plain = parse_scene("name = \"p\"\ncoordinates = [\"x\"]\nlagrangian = \"x'^2/2\"\n", "plain.toml");
  CHECK(!plain.optimize.present);
  CHECK_THROWS_WITH(optimize::read_settings(plain),
                    "plain.toml: error: the scene has no [optimize] table (docs/scenes.md, \"Optimal motions\")");
}

TEST_CASE("a free final time: the loop's cost 2 pi a/T plus T is least at T = sqrt(2 pi a)", "[optimize]") {
  std::string text = heisenberg(0.5, 1.0);
  text.replace(text.find("t_end = 1"), 9, "t_end = [0.5, 4.0]\nfinal_cost = \"t\"");
  const Scene scene = parse_scene(text, "heisenberg.toml");
  const optimize::Settings settings = optimize::read_settings(scene);
  REQUIRE(settings.free_time());
  optimize::HermiteSimpson problem(scene, settings, 50);
  const optimize::Solution solution = optimize::solve(problem, problem.straight_line());
  REQUIRE(solution.status == optimize::Solution::Status::optimal);
  const double t_end = std::sqrt(2 * M_PI * 0.5);
  CHECK(std::abs(problem.final_time(solution.z.data()) - t_end) < 1e-6 * t_end);
  CHECK(std::abs(solution.cost - 2 * t_end) < 1e-6 * 2 * t_end);
}

TEST_CASE("a final condition as a bound: the loop encloses the least area the bound allows", "[optimize]") {
  // z(T) = [0.5, 0.8]: the cost 2 pi z(T)/T grows with the area, so the optimum is the circle of
  // area 0.5 at cost pi; z(T) = [-0.8, -0.3] is the circle run the other way, of area 0.3.
  for (const auto& [bound, area] : {std::pair{"[0.5, 0.8]", 0.5}, std::pair{"[-0.8, -0.3]", 0.3}}) {
    std::string text = heisenberg(0.5, 1.0);
    text.replace(text.rfind("z = 0.5"), 7, std::string("z = ") + bound);
    INFO(bound);
    const Optimum o = solve(text, 50);
    REQUIRE(o.solution.status == optimize::Solution::Status::optimal);
    CHECK(std::abs(o.solution.cost - 2 * M_PI * area) < 1e-6 * 2 * M_PI * area);
  }
}

TEST_CASE("a bound on a named quantity is a bound along the path", "[optimize]") {
  // The same cut as a bound on x itself (above), written on an [outputs] quantity: the same optimum.
  const Optimum direct = solve(heisenberg(0.5, 1.0, "x = [-0.3, 0.3]\n"), 30);
  const Optimum named = solve(heisenberg(0.5, 1.0, "across = [-0.3, 0.3]\n") + "[outputs]\nacross = \"x\"\n", 30);
  REQUIRE(direct.solution.status == optimize::Solution::Status::optimal);
  REQUIRE(named.solution.status == optimize::Solution::Status::optimal);
  CHECK(std::abs(named.solution.cost - direct.solution.cost) < 1e-7 * direct.solution.cost);
  CHECK(named.solution.cost > 2 * M_PI * 0.5 * (1 + 1e-3));
  // A row's bounds, unlike a variable's, are met within IPOPT's relaxation of them
  // (bound_relax_factor 1e-10 times max(1, |bound|), solve.cpp).
  for (double x : named.x) CHECK(std::abs(x) <= 0.3 + 2e-10);
}
