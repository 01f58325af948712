// nhc optimize on scenes with [inputs] (docs/optimize.md): the exact Hessian against finite
// differences of the exact gradients; the optimum against IDA (the optimal inputs replayed from
// the optimal initial state: the end state agrees within the transcription's error, which falls at
// the method's order as the intervals are halved); bounds that hold at every point.
#include <catch2/catch.hpp>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "nhc/jit.hpp"
#include "nhc/optimize/hermite_simpson.hpp"
#include "nhc/optimize/path_table.hpp"
#include "nhc/optimize/settings.hpp"
#include "nhc/optimize/solve.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"

using namespace nhc;
namespace fs = std::filesystem;
namespace rt = nhc::runtime;

namespace {

/// examples/car_parking.toml, its horizon and objective replaced when given.
std::string car_parking(const std::string& replace_t_end = "", const std::string& objective = "(F^2 + tau^2)/2") {
  std::ifstream in(std::string(NHC_SOURCE_DIR) + "/examples/car_parking.toml");
  std::stringstream text;
  text << in.rdbuf();
  std::string s = text.str();
  const std::string fixed = "[optimize]\nobjective = \"(F^2 + tau^2)/2\"\nt_end = 12.0\n";
  const std::size_t at = s.find(fixed);
  REQUIRE(at != std::string::npos);
  s.replace(at, fixed.size(),
            "[optimize]\nobjective = \"" + objective +
                "\"\nt_end = " + (replace_t_end.empty() ? "12.0" : replace_t_end) + "\n");
  return s;
}

/// grad_z (sigma f + sum lambda_r g_r) from the exact first derivatives.
std::vector<double> lagrangian_gradient(optimize::HermiteSimpson& p, const std::vector<double>& z, double sigma,
                                        const std::vector<double>& lambda) {
  std::vector<double> grad(z.size());
  p.objective_gradient(z.data(), grad.data());
  for (double& g : grad) g *= sigma;
  std::vector<int> rows(static_cast<std::size_t>(p.jacobian_nonzeros())), columns(rows.size());
  std::vector<double> values(rows.size());
  p.jacobian_structure(rows.data(), columns.data());
  p.jacobian_values(z.data(), values.data());
  for (std::size_t e = 0; e < rows.size(); ++e)
    grad[static_cast<std::size_t>(columns[e])] += lambda[static_cast<std::size_t>(rows[e])] * values[e];
  return grad;
}

void check_hessian(const std::string& text) {
  const Scene scene = parse_scene(text, "car_parking.toml");
  const optimize::Settings settings = optimize::read_settings(scene);
  optimize::HermiteSimpson p(scene, settings, 3);
  std::vector<double> z = p.straight_line();
  for (std::size_t k = 0; k < z.size(); ++k) z[k] += 0.1 * std::sin(1.3 * static_cast<double>(k) + 0.2);
  if (settings.free_time()) z.back() = 10.5;
  std::vector<double> lambda(static_cast<std::size_t>(p.constraints()));
  for (std::size_t r = 0; r < lambda.size(); ++r) lambda[r] = std::cos(0.7 * static_cast<double>(r));
  const double sigma = 0.8;

  std::vector<int> rows(static_cast<std::size_t>(p.hessian_nonzeros())), columns(rows.size());
  std::vector<double> values(rows.size());
  p.hessian_structure(rows.data(), columns.data());
  p.hessian_values(z.data(), sigma, lambda.data(), values.data());
  std::map<std::pair<int, int>, double> exact;
  for (std::size_t e = 0; e < rows.size(); ++e) {
    REQUIRE(rows[e] >= columns[e]);
    exact[{rows[e], columns[e]}] += values[e];
  }
  // Central differences of the exact gradient, column by column: every entry of the lower
  // triangle, in or out of the structure (out of it the difference must vanish).
  const double eps = 1e-6;
  double worst = 0;
  for (std::size_t c = 0; c < z.size(); ++c) {
    std::vector<double> plus = z, minus = z;
    plus[c] += eps;
    minus[c] -= eps;
    const std::vector<double> gp = lagrangian_gradient(p, plus, sigma, lambda),
                              gm = lagrangian_gradient(p, minus, sigma, lambda);
    for (std::size_t r = c; r < z.size(); ++r) {
      const double fd = (gp[r] - gm[r]) / (2 * eps);
      const auto it = exact.find({static_cast<int>(r), static_cast<int>(c)});
      const double value = it == exact.end() ? 0.0 : it->second;
      worst = std::max(worst, std::abs(fd - value) / (1 + std::abs(value)));
    }
  }
  INFO("largest difference " << worst << " over " << z.size() << " variables");
  CHECK(worst < 1e-6);
}

}  // namespace

TEST_CASE("the exact Hessian of the Lagrangian equals differences of the exact gradients (fixed and free T)",
          "[optimize][inputs]") {
  // An objective and a final cost of t too, so that every term of the free T's row counts.
  const std::string objective =
      "(F^2 + tau^2)/2 + t^2*x'*theta + sin(t)*phi^2*F\"\nfinal_cost = \"t*x^2 + y'*t^2 + t^3";
  check_hessian(car_parking("", objective));
  check_hessian(car_parking("[8.0, 14.0]", objective));
}

namespace {

struct Replay {
  double end_error = 0;    ///< largest |IDA - collocation| over the coordinates and rates at T
  double worst_bound = 0;  ///< largest excess of phi over 0.5 at any point
};

/// The car parked with N intervals, its optimal inputs (quadratic through each interval's three
/// points, as Hermite–Simpson's controls are) replayed by IDA from the optimal initial state.
Replay replay(const Scene& scene, const rt::Model& model, int intervals) {
  const optimize::Settings settings = optimize::read_settings(scene);
  optimize::HermiteSimpson p(scene, settings, intervals);
  const optimize::Solution s = optimize::solve(p, p.straight_line());
  REQUIRE(s.status == optimize::Solution::Status::optimal);
  const std::vector<double>& z = s.z;
  const double T = p.final_time(z.data()), h = T / intervals;
  const rt::InputFunction inputs = [&](double t, const double*, double* u) {
    const int k = std::clamp(static_cast<int>(t / h), 0, intervals - 1);
    const double x = (t - k * h) / h;  // 0, 1/2, 1 at the interval's points
    for (int i = 0; i < p.inputs(); ++i) {
      const double a = z[static_cast<std::size_t>(p.u_index(2 * k, i))],
                   m = z[static_cast<std::size_t>(p.u_index(2 * k + 1, i))],
                   b = z[static_cast<std::size_t>(p.u_index(2 * k + 2, i))];
      u[i] = a * 2 * (x - 0.5) * (x - 1) - m * 4 * x * (x - 1) + b * 2 * x * (x - 0.5);  // Lagrange basis
    }
  };
  const optimize::PointProblem& pp = p.point_problem();
  auto state = [&](int point, const std::string& name) {
    const auto it = std::find(pp.state_names.begin(), pp.state_names.end(), name);
    REQUIRE(it != pp.state_names.end());
    return z[static_cast<std::size_t>(p.q_index(point, static_cast<int>(it - pp.state_names.begin())))];
  };
  std::map<std::string, std::vector<double>> initial;
  for (const std::string& c : scene.jet->coordinates()) initial[c] = {state(0, c), state(0, c + "'")};
  rt::IntegratorOptions options;
  options.rtol = 1e-12;
  options.atol = 1e-13;
  const rt::RunResult run = rt::simulate(model, {}, rt::initial_state_from(model, 0.0, initial),
                                         rt::output_times(0.0, T, 1), options, {}, inputs);
  REQUIRE_FALSE(run.failure);
  Replay out;
  const rt::Sample& end = run.samples.back();
  for (const std::string& c : scene.jet->coordinates())
    for (const std::string& name : {c, c + "'"})
      for (int k = 0; k < model.n_states(); ++k)
        if (model.state_name(k) == name)
          out.end_error =
              std::max(out.end_error, std::abs(end.y[static_cast<std::size_t>(k)] - state(p.points() - 1, name)));
  for (int j = 0; j < p.points(); ++j) out.worst_bound = std::max(out.worst_bound, std::abs(state(j, "phi")) - 0.5);
  return out;
}

}  // namespace

TEST_CASE("the optimal car parking satisfies the DAE between the points at order 4 and its steering bound holds",
          "[optimize][inputs]") {
  const Scene scene = parse_scene(car_parking(), "car_parking.toml");
  jit::BuildOptions build;
  build.compile.cache_directory = fs::path(NHC_BINARY_DIR) / "tests" / "optimize" / "jit-cache";
  const jit::LoadedModel built = jit::build(scene, ModelKind::chetaev, build);
  std::vector<double> errors;
  for (int n : {15, 30, 60}) {
    const Replay r = replay(scene, built.model(), n);
    errors.push_back(r.end_error);
    CHECK(r.worst_bound <= 0.0);
  }
  INFO("end-state errors " << errors[0] << " " << errors[1] << " " << errors[2]);
  const double order1 = std::log2(errors[0] / errors[1]), order2 = std::log2(errors[1] / errors[2]);
  INFO("orders " << order1 << " " << order2);
  CHECK(errors[2] < 1e-3);
  CHECK(order2 > 3.5);
}
