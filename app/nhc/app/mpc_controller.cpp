#include "nhc/app/mpc_controller.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "nhc/base/clock.hpp"
#include "nhc/errors.hpp"
#include "nhc/optimize/hermite_simpson.hpp"
#include "nhc/optimize/settings.hpp"
#include "nhc/optimize/solve.hpp"
#include "nhc/base/number_text.hpp"

namespace nhc::app {

namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Where the fraction s of the horizon falls among the plan's points: between points a and b, at
/// weight w on b (linear interpolation; beyond the last point, the last point's values).
struct Between {
  int a = 0, b = 0;
  double w = 0;
};
Between between(const optimize::HermiteSimpson& p, double s) {
  Between at;
  while (at.a + 1 < p.points() - 1 && p.fraction(at.a + 1) <= s) ++at.a;
  at.b = std::min(at.a + 1, p.points() - 1);
  const double span = p.fraction(at.b) - p.fraction(at.a);
  at.w = span > 0 ? std::clamp((s - p.fraction(at.a)) / span, 0.0, 1.0) : 0.0;
  return at;
}

}  // namespace

MpcController::MpcController(const Scene& scene, const runtime::Model& model, const SceneMpc& mpc)
    : model_(&model), settings_(mpc) {
  if (scene.inputs.empty())
    throw InputError(mpc.where,
                     "mpc sets the inputs of [inputs], and the scene has none (model predictive control plans "
                     "the inputs of a driven model)");
  optimize::Settings settings;
  try {
    settings = optimize::read_settings(scene);
  } catch (const InputError& e) {
    if (e.where().line > 0) throw;  // a fault inside the table, at its place
    throw InputError(mpc.where,
                     "mpc solves the scene's [optimize] problem at each sample, and the scene has no [optimize] "
                     "table (its objective, bounds and final conditions: docs/mpc.md)");
  }
  // The receding horizon: [t_k, t_k + horizon]; [optimize]'s t_end and [optimize.initial] do not apply.
  settings.initial.clear();
  settings.t_end_low = settings.t_end_high = scene.initial.t0 + mpc.horizon;
  optimize::PointProblem problem = optimize::point_problem(scene, settings);
  // The first point's differential states are the measured state (its rates, multipliers and
  // inputs follow from the equations and the optimum).
  for (int k = 0; k < problem.states; ++k) {
    if (!problem.collocated[static_cast<std::size_t>(k)]) continue;
    const std::string& name = problem.state_names[static_cast<std::size_t>(k)];
    int found = -1;
    for (int i = 0; i < model.n_states(); ++i)
      if (model.state_name(i) == name) found = i;
    if (found < 0)
      throw InputError(mpc.where, "mpc: the state " + name + " of the " + to_string(problem.model) +
                                      " model that [optimize] plans with is not a state of the run's model (give "
                                      "[optimize] model = the run's model)");
    start_states_.push_back(found);
    problem.initial.push_back({k, 0.0, 0.0, name, mpc.where});
  }
  problem.measured_start = true;
  held_.assign(static_cast<std::size_t>(model.n_inputs()), false);
  for (int k = 0; k < problem.inputs; ++k) {
    const SceneInput& input = scene.inputs.at(static_cast<std::size_t>(k));
    const int i = input.feedback ? -1 : model.input_index(problem.input_names[static_cast<std::size_t>(k)]);
    input_slots_.push_back(i);
    if (i >= 0) held_[static_cast<std::size_t>(i)] = true;
  }
  problem_ = std::make_unique<optimize::HermiteSimpson>(scene, settings, std::move(problem), mpc.intervals);
}

MpcController::~MpcController() = default;

const std::vector<std::string>& MpcController::columns() {
  static const std::vector<std::string> names{"mpc:cost", "mpc:iterations", "mpc:seconds"};
  return names;
}

std::vector<double> MpcController::column_values(bool at_sample) const {
  if (!at_sample || solves_.empty()) return std::vector<double>(3, std::numeric_limits<double>::quiet_NaN());
  const MpcSolve& s = solves_.back();
  return {s.cost, static_cast<double>(s.iterations), s.seconds};
}

std::string MpcController::summary() const {
  std::vector<double> seconds, iterations;
  long failed = 0;
  for (const MpcSolve& s : solves_) {
    seconds.push_back(s.seconds);
    iterations.push_back(s.iterations);
    if (!s.converged) ++failed;
  }
  const double worst = seconds.empty() ? 0 : *std::max_element(seconds.begin(), seconds.end());
  const double most = iterations.empty() ? 0 : *std::max_element(iterations.begin(), iterations.end());
  return "model predictive control: " + std::to_string(solves_.size()) + " solves, median " +
         base::number_text(median(seconds), 3) + " s, max " + base::number_text(worst, 3) + " s, " +
         std::to_string(failed) + " not converged (IPOPT iterations: median " +
         base::number_text(median(iterations), 3) + ", max " + base::number_text(most, 3) + ")";
}

// The last plan moved to the horizon [t, t + H]: each variable of the new point j is the old
// plan's at t_j by linear interpolation between its points (the last point's beyond its end),
// clamped into the bounds.
std::vector<double> MpcController::shifted_plan(const std::vector<double>& plan, double plan_t0, double t) const {
  optimize::HermiteSimpson& p = *problem_;
  std::vector<double> z(plan.size());
  const int stride = p.points() > 1 ? p.q_index(1, 0) - p.q_index(0, 0) : 0;
  const double length = settings_.horizon;
  for (int j = 0; j < p.points(); ++j) {
    const auto [a, b, w] = between(p, std::clamp((t + length * p.fraction(j) - plan_t0) / length, 0.0, 1.0));
    for (int k = 0; k < stride; ++k) {
      const auto to = static_cast<std::size_t>(j * stride + k);
      z[to] =
          (1 - w) * plan[static_cast<std::size_t>(a * stride + k)] + w * plan[static_cast<std::size_t>(b * stride + k)];
    }
  }
  for (std::size_t k = 0; k < z.size(); ++k)
    z[k] = std::clamp(z[k], p.variable_low(static_cast<int>(k)), p.variable_high(static_cast<int>(k)));
  return z;
}

// The last plan's inputs at t (linear between its points).
std::vector<double> MpcController::plan_inputs(double t) const {
  const optimize::HermiteSimpson& p = *problem_;
  const auto [a, b, w] = between(p, std::clamp((t - plan_t0_) / settings_.horizon, 0.0, 1.0));
  std::vector<double> u;
  for (int k = 0; k < p.inputs(); ++k)
    u.push_back((1 - w) * plan_[static_cast<std::size_t>(p.u_index(a, k))] +
                w * plan_[static_cast<std::size_t>(p.u_index(b, k))]);
  return u;
}

std::vector<double> MpcController::operator()(const runtime::Sample& reached) {
  optimize::HermiteSimpson& p = *problem_;
  std::vector<double> start;
  for (int i : start_states_) start.push_back(reached.y.at(static_cast<std::size_t>(i)));
  p.restart(reached.t, start);
  std::vector<double> guess;
  if (!plan_.empty() && settings_.warm_start) {
    guess = shifted_plan(plan_, plan_t0_, reached.t);
  } else if (!iterate_.empty() && settings_.warm_start) {
    guess = shifted_plan(iterate_, iterate_t0_, reached.t);
  } else {
    guess = p.straight_line();
  }
  optimize::SolveOptions options;
  options.max_iterations = settings_.max_iterations;
  options.tolerance = settings_.tolerance;
  const auto started = base::Clock::now();
  const optimize::Solution solution = optimize::solve(p, guess, options);
  MpcSolve record;
  record.t = reached.t;
  record.seconds = base::seconds_since(started);
  record.cost = solution.cost;
  record.iterations = solution.iterations;
  record.converged = solution.status == optimize::Solution::Status::optimal;
  solves_.push_back(record);
  std::vector<double> first;
  if (record.converged) {
    plan_ = solution.z;
    plan_t0_ = reached.t;
    for (int k = 0; k < p.inputs(); ++k) first.push_back(plan_[static_cast<std::size_t>(p.u_index(0, k))]);
  } else if (!plan_.empty()) {
    first = plan_inputs(reached.t);  // the last good plan's input now
  } else {
    // No plan yet: the last iterate's first input, within its bounds; the next solve starts
    // from that iterate (shifted) rather than from the straight line again.
    for (int k = 0; k < p.inputs(); ++k) {
      const int v = p.u_index(0, k);
      first.push_back(std::clamp(solution.z.at(static_cast<std::size_t>(v)), p.variable_low(v), p.variable_high(v)));
    }
    iterate_ = solution.z;
    iterate_t0_ = reached.t;
  }
  std::vector<double> u = reached.u;
  u.resize(static_cast<std::size_t>(model_->n_inputs()), 0.0);
  for (std::size_t k = 0; k < input_slots_.size(); ++k)
    if (input_slots_[k] >= 0) u[static_cast<std::size_t>(input_slots_[k])] = first[k];
  return u;
}

SampleLaw sample_law(std::shared_ptr<MpcController> controller) {
  return [controller](const runtime::Sample& reached) { return (*controller)(reached); };
}

}  // namespace nhc::app
