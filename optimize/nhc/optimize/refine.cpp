#include "nhc/optimize/refine.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace nhc::optimize {

namespace {

/// The local error falls as h^4 (docs/optimize.md, "Path error"): interval k split into
/// ceil((e_k / target)^(1/4)) pieces, at most 8, where target = tolerance / intervals so that the
/// local errors' sum meets the tolerance.
std::vector<double> split(const HermiteSimpson& problem, const PathError& error, double tolerance) {
  const std::vector<double> mesh = problem.mesh();
  const double target = tolerance / problem.intervals();
  std::vector<double> out{0.0};
  bool any = false;
  for (int k = 0; k < problem.intervals(); ++k) {
    const double e = error.local[static_cast<std::size_t>(k)];
    int pieces = 1;
    if (!std::isfinite(e)) pieces = 8;
    else if (e > target) pieces = std::clamp(static_cast<int>(std::ceil(std::pow(e / target, 0.25))), 2, 8);
    if (k == error.interval) pieces = std::max(pieces, 2);
    any = any || pieces > 1;
    const double a = mesh[static_cast<std::size_t>(k)], b = mesh[static_cast<std::size_t>(k) + 1];
    for (int p = 1; p <= pieces; ++p) out.push_back(p == pieces ? b : a + (b - a) * p / pieces);
  }
  (void)any;
  return out;
}

std::vector<double> equal(int intervals) {
  std::vector<double> mesh;
  for (int k = 0; k <= intervals; ++k) mesh.push_back(static_cast<double>(k) / intervals);
  return mesh;
}

bool converged(const Solution& s) {
  return s.status == Solution::Status::optimal || s.status == Solution::Status::acceptable;
}

}  // namespace

std::vector<double> perturbed_start(const HermiteSimpson& problem, const std::vector<double>& start, unsigned seed,
                                    double amplitude) {
  constexpr double kPi = 3.14159265358979323846;
  std::mt19937 generator(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<double> z = start;
  const double D = problem.final_time(z.data()) - problem.initial_time();
  const PointProblem& p = problem.point_problem();
  for (int i = 0; i < p.states; ++i) {
    if (!p.collocated[static_cast<std::size_t>(i)]) continue;
    double scale = 1;
    for (int j = 0; j < problem.points(); ++j)
      scale = std::max(scale, std::abs(z[static_cast<std::size_t>(problem.q_index(j, i))]));
    double a[3];
    for (double& c : a) c = amplitude * scale * uniform(generator);
    for (int j = 0; j < problem.points(); ++j) {
      const double s = problem.fraction(j);
      for (int m = 1; m <= 3; ++m) {
        z[static_cast<std::size_t>(problem.q_index(j, i))] += a[m - 1] * std::sin(m * kPi * s);
        z[static_cast<std::size_t>(problem.v_index(j, i))] += a[m - 1] * m * kPi / D * std::cos(m * kPi * s);
      }
    }
  }
  for (std::size_t k = 0; k < z.size(); ++k)
    z[k] = std::clamp(z[k], problem.variable_low(static_cast<int>(k)), problem.variable_high(static_cast<int>(k)));
  return z;
}

Outcome solve_refined(const HermiteSimpson& problem, const std::vector<double>& guess,
                      const SolveOptions& solve_options, const RefineOptions& options) {
  // Continuation: N, N/4, N/16, … down to the first below 4 times the coarsest, solved coarse to fine.
  std::vector<int> schedule{options.intervals};
  while (schedule.back() >= 4 * options.coarsest) schedule.push_back((schedule.back() + 3) / 4);
  std::reverse(schedule.begin(), schedule.end());
  if (!guess.empty() && !options.continuation_from_guess)
    schedule = {options.intervals};  // a guess is the continuation's start itself

  Outcome out;
  auto current = std::make_shared<HermiteSimpson>(problem);
  std::vector<double> z;
  std::shared_ptr<HermiteSimpson> previous;
  auto say = [&](const std::string& line) {
    if (options.report) options.report(line);
  };
  auto start_from = [&](const std::shared_ptr<HermiteSimpson>& next) {
    if (previous) return transfer(*previous, z, *next);
    if (guess.empty()) return next->straight_line();
    return transfer(problem, guess, *next);
  };
  auto run = [&](const std::shared_ptr<HermiteSimpson>& next, bool measure, const std::string& label) {
    const std::vector<double> start = start_from(next);
    Round round;
    round.intervals = next->intervals();
    round.solution = solve(*next, start, solve_options);
    if (round.solution.status == Solution::Status::acceptable) {
      // An acceptable-level stop is retried once from where it stopped.
      Solution again = solve(*next, round.solution.z, solve_options);
      again.iterations += round.solution.iterations;
      round.solution = std::move(again);
    }
    if (measure && converged(round.solution)) {
      round.error = path_error(*next, round.solution.z);
      round.measured = true;
    }
    std::string line =
        fmt::format("{}: {} intervals, {} iterations, ", label, next->intervals(), round.solution.iterations);
    if (converged(round.solution)) {
      line += fmt::format("cost {:.12g}, violation {:.2g}", round.solution.cost, round.solution.violation);
      if (round.solution.status == Solution::Status::acceptable) line += " (IPOPT's acceptable level)";
    } else {
      line += round.solution.words;
    }
    if (round.measured) line += fmt::format(", path error {:.3g}", round.error.error);
    say(line);
    // A failed coarse solve still hands on its last point: a start no worse than a fresh line.
    previous = next;
    z = round.solution.z;
    out.rounds.push_back(round);
    return round;
  };

  int number = 0;
  for (std::size_t s = 0; s < schedule.size(); ++s) {
    const bool last = s + 1 == schedule.size();
    current = std::make_shared<HermiteSimpson>(problem.remeshed(equal(schedule[s])));
    run(current, last, fmt::format("round {}", ++number));
  }
  for (int refinement = 0;; ++refinement) {
    const Round& round = out.rounds.back();
    out.problem = current;
    out.solution = round.solution;
    out.error = round.error;
    out.measured = round.measured;
    if (!converged(round.solution)) {
      out.status = Outcome::Status::solver;
      return out;
    }
    if (round.error.error <= options.path_tolerance) {
      out.status = Outcome::Status::optimal;
      return out;
    }
    const std::string at = fmt::format("interval {} [{:.6g}, {:.6g}] of {}", round.error.interval + 1,
                                       round.error.t_low, round.error.t_high, current->intervals());
    out.status = Outcome::Status::path_error;
    if (refinement >= options.max_rounds) {
      out.words =
          fmt::format("the path error {:.3g} is above the tolerance {:.3g} after {} refinements; largest in {} ({})",
                      round.error.error, options.path_tolerance, refinement, at, round.error.where);
      return out;
    }
    if (refinement > 0) {
      // Each refinement must pay: the error of a path of the continuous problem falls as h^4;
      // one that falls slower than h^2 over a refinement belongs to no continuous path (a
      // spurious discrete mode, docs/optimize.md, "Path error").
      const Round& before = out.rounds[out.rounds.size() - 2];
      const double ratio = static_cast<double>(round.intervals) / before.intervals;
      if (before.measured && std::isfinite(before.error.error) &&
          round.error.error > before.error.error / (ratio * ratio)) {
        out.words = fmt::format(
            "the path error does not fall with refinement ({:.3g} at {} intervals, {:.3g} at {}): the discrete optimum "
            "is no path of the continuous problem; largest in {} ({})",
            before.error.error, before.intervals, round.error.error, round.intervals, at, round.error.where);
        return out;
      }
    }
    std::vector<double> mesh = split(*current, round.error, options.path_tolerance);
    if (static_cast<int>(mesh.size()) - 1 > options.max_intervals) {
      out.words = fmt::format(
          "the path error {:.3g} is above the tolerance {:.3g}, and meeting it needs more than {} intervals; largest "
          "in {} ({})",
          round.error.error, options.path_tolerance, options.max_intervals, at, round.error.where);
      return out;
    }
    current = std::make_shared<HermiteSimpson>(problem.remeshed(std::move(mesh)));
    run(current, true, fmt::format("round {} (refined where the local error is large)", ++number));
  }
}

}  // namespace nhc::optimize
