// nhc optimize SCENE [-o FILE.csv] [--intervals N] [--guess FILE.csv] [--plot DIR] [--max-iterations N]
//                    [--tolerance E] [--jacobian exact|finite-differences] [--hessian exact|limited-memory]
//                    [--set NAME=VALUE]...
//
// An optimal motion (docs/optimize.md): the scene's [optimize] table transcribed by
// Hermite–Simpson collocation and solved by IPOPT (nhc::optimize). Prints `cost = C`, the
// constraint violation and the iterations; writes t, the states, their rates and the inputs on the
// collocation points. IPOPT's progress goes to stderr. Infeasible or iteration limit: exit 3
// in words naming the constraint violated most (at the iteration limit the last point is written).
#include <fmt/format.h>

#include <algorithm>
#include <iostream>

#include "command_programs.hpp"
#include "commands.hpp"
#include "flag_rules.hpp"
#include "nhc/app/optimize_options.hpp"
#include "nhc/app/optimize_request.hpp"
#include "nhc/app/parameter_overrides.hpp"
#include "nhc/base/number_text.hpp"
#include "nhc/io/atomic_directory.hpp"
#include "nhc/io/atomic_file.hpp"
#include "nhc/io/csv_file.hpp"
#include "nhc/io/output_path.hpp"
#include "nhc/optimize/hermite_simpson.hpp"
#include "nhc/optimize/path_table.hpp"
#include "nhc/optimize/refine.hpp"
#include "nhc/optimize/settings.hpp"
#include "nhc/optimize/solve.hpp"
#include "nhc/scene/scene.hpp"
#include "plots.hpp"
#include "trajectory_plots.hpp"

namespace nhc::cli {

namespace {

struct OptimizeOptions {
  std::string scene_path, output, guess, plot;
  std::vector<std::string> set;  ///< --set NAME=VALUE, as nhc simulate's
  int starts = 1;
  unsigned seed = 1;
  app::OptimizeRequest request;
};

/// The starting path from a CSV with a header (nhc simulate's or optimize's): t, each coordinate,
/// the other states, rates and inputs where present (path_table.hpp).
std::vector<double> guess_from_file(const Scene& scene, const optimize::HermiteSimpson& problem,
                                    const std::string& path) {
  // The data-file rules (docs/safety.md): a regular file within the size limit, finite numbers,
  // every fault at its line and column.
  const CsvFile file = read_csv_file(path, "a CSV file for --guess");
  return optimize::guess_from_table(problem, file.header, file.numbers(), scene, "--guess", path);
}

void write_path(std::ostream& out, const optimize::HermiteSimpson& problem, const std::vector<double>& z) {
  const std::vector<std::string> columns = optimize::path_columns(problem);
  for (std::size_t c = 0; c < columns.size(); ++c) out << (c ? "," : "") << columns[c];
  out << "\n";
  // Each number once in its shortest round-trip form (0.1, not 0.10000000000000001), as every
  // data file nhc writes (base/number_text.hpp).
  for (const std::vector<double>& row : optimize::path_rows(problem, z)) {
    std::string line = base::shortest_text(row.at(0));  // t
    for (std::size_t c = 1; c < row.size(); ++c) base::append_shortest(line, ',', row[c]);
    out << line << '\n';
  }
}

/// `--plot DIR`: the path's CSV, the coordinates and the rates against t, the path in the plane
/// of the first two coordinates, and plots.md (plots.hpp), written atomically.
void write_plots(const std::string& directory, const Scene& scene, const optimize::HermiteSimpson& problem,
                 const std::vector<double>& z, const std::vector<std::string>& inputs, const std::string& summary) {
  AtomicDirectory out(directory, inputs);
  const std::string csv = scene.name + "_optimal.csv";
  write_file_atomically(out.file(csv), [&](std::ostream& o) { write_path(o, problem, z); });
  Plot coordinates{"coordinates", "coordinates", "t", "", false, false, {}};
  Plot rates{"rates", problem.inputs() ? "rates" : "rates (the controls)", "t", "", false, false, {}};
  Plot inputs_plot{"inputs", "inputs (the controls)", "t", "", false, false, {}};
  const std::vector<std::string> columns = optimize::path_columns(problem);
  auto has = [&](const std::string& c) { return std::find(columns.begin(), columns.end(), c) != columns.end(); };
  for (const std::string& name : scene.jet->coordinates()) {
    coordinates.curves.push_back({name, csv, "t", name});
    if (has(name + "'")) rates.curves.push_back({name + "'", csv, "t", name + "'"});
  }
  for (const std::string& u : problem.point_problem().input_names) inputs_plot.curves.push_back({u, csv, "t", u});
  std::vector<Plot> plots{coordinates, rates};
  if (!inputs_plot.curves.empty()) plots.push_back(inputs_plot);
  const PathPlane plane = path_plane(scene, "", "--plot");
  if (!plane.y.empty()) plots.push_back(path_plot("path", "path", plane, {{"optimal", csv}}));
  draw_plots(out.path(), plots);
  write_file_atomically(out.file("plots.md"), [&](std::ostream& o) {
    o << "# " << scene.name << ": optimal motion\n\nDrawn by `nhc optimize --plot` from [" << csv << "](" << csv
      << ") (t, the states, their rates and the inputs on the " << problem.points() << " collocation points). "
      << summary << "\n\n"
      << markdown_images(plots);
  });
  out.commit();
}

}  // namespace

CommandRunner add_optimize_command(CLI::App& app) {
  auto options = std::make_shared<OptimizeOptions>();
  CLI::App* sub = app.add_subcommand("optimize", command_description("optimize"));
  sub->add_option("SCENE", options->scene_path, "scene file (TOML) with an [optimize] table")->required();
  sub->add_option(
      "-o,--output", options->output,
      "CSV file for the optimal path (t, the states and their rates, the inputs; nhc animate --path draws it)");
  // The values' rules are app::check_optimize_request's, shared with Python.
  sub->add_option("--intervals", options->request.intervals,
                  "collocation intervals (default: [optimize] intervals, else 40)");
  sub->add_option("--guess", options->guess,
                  "start from this path (CSV with t and the coordinates, e.g. nhc simulate's or a previous optimum)");
  sub->add_option("--plot", options->plot, "directory for plots (SVG, PNG) of the coordinates, rates, inputs and path");
  sub->add_option("--jacobian", options->request.jacobian,
                  "exact (the default) or finite-differences: IPOPT's own differences on the same sparsity");
  sub->add_option(
      "--hessian", options->request.hessian,
      "exact (the default: second derivatives of the same functions) or limited-memory (IPOPT's quasi-Newton)");
  sub->add_option("--max-iterations", options->request.max_iterations, "IPOPT iterations (default 3000)");
  sub->add_option("--tolerance", options->request.tolerance,
                  "IPOPT's tolerance on the scaled optimality error (default 1e-10)");
  sub->add_option("--starts", options->starts,
                  "solve from this many starts: the default (or --guess) and K - 1 seeded smooth perturbations of it; "
                  "reports every cost found and keeps the lowest (the optimum is local)")
      ->check(CLI::Range(1, 1000));
  sub->add_option("--seed", options->seed, "seed of the perturbed starts (default 1)");
  sub->add_option(
      "--path-tolerance", options->request.path_tolerance,
      "largest path error accepted, relative to the states' scale (default 1e-6); above it the mesh is refined");
  add_set_option(sub, options->set);

  return [options]() {
    const app::OptimizeRequest& request = options->request;
    app::check_optimize_request(request, app::optimize_command_line_names());
    Scene scene = load_scene(options->scene_path);
    // --set: the parameters replaced and everything written through them (the [initial] values,
    // t0, [simulate]) re-evaluated by app::set_parameter_values, Python's set= rule; [optimize]'s
    // numbers and expressions take the values as the problem is read (optimize::read_settings).
    app::apply_parameter_overrides(scene, app::parse_parameter_overrides(scene, options->set));
    const optimize::Settings settings = optimize::read_settings(scene);
    if (!options->output.empty()) check_output_file(options->output, {options->scene_path, options->guess});
    if (!options->plot.empty()) {
      require_gnuplot("--plot");
      check_output_directory(options->plot, {options->scene_path, options->guess});
    }
    const optimize::HermiteSimpson problem(scene, settings,
                                           static_cast<int>(request.intervals.value_or(settings.intervals)));
    const std::vector<double> guess =
        options->guess.empty() ? std::vector<double>{} : guess_from_file(scene, problem, options->guess);

    std::cout << "nhc optimize: " << scene.name << ", "
              << (problem.inputs() ? "the " + to_string(problem.point_problem().model) + " model driven by its inputs"
                                   : std::string("the vakonomic problem"))
              << ", " << problem.intervals() << " Hermite-Simpson intervals, " << problem.variables() << " variables, "
              << problem.constraints() << " constraints; t_end "
              << (settings.free_time() ? fmt::format("free in [{}, {}]", settings.t_end_low, settings.t_end_high)
                                       : fmt::format("{}", settings.t_end_low))
              << "; start: " << (options->guess.empty() ? "straight line" : options->guess) << "\n";
    std::cout.flush();

    optimize::SolveOptions solve_options = app::solve_options(request);
    solve_options.progress = [](int iteration, double cost, double violation) {
      std::cerr << fmt::format("  iteration {:4d}: cost {:.10g}, violation {:.3g}\n", iteration, cost, violation);
      return true;
    };
    optimize::RefineOptions refine_options = app::refine_options(request, problem.intervals());
    refine_options.report = [](const std::string& line) {
      std::cout << "  " << line << "\n";
      std::cout.flush();
    };
    optimize::Outcome outcome = optimize::solve_refined(problem, guess, solve_options, refine_options);
    if (options->starts > 1) {
      // Local optima said aloud: each start's cost, the lowest kept.
      std::vector<std::string> found{outcome.status == optimize::Outcome::Status::optimal
                                         ? fmt::format("{:.10g}", outcome.solution.cost)
                                         : std::string("none")};
      const std::vector<double> base = guess.empty() ? problem.straight_line() : guess;
      optimize::RefineOptions perturbed = refine_options;
      perturbed.continuation_from_guess = guess.empty();
      for (int k = 1; k < options->starts; ++k) {
        std::cout << "  start " << k + 1 << " of " << options->starts << " (perturbed, seed "
                  << options->seed + static_cast<unsigned>(k) - 1 << "):\n";
        optimize::Outcome other = optimize::solve_refined(
            problem, optimize::perturbed_start(problem, base, options->seed + static_cast<unsigned>(k) - 1),
            solve_options, perturbed);
        const bool good = other.status == optimize::Outcome::Status::optimal;
        found.push_back(good ? fmt::format("{:.10g}", other.solution.cost) : std::string("none"));
        if (good &&
            (outcome.status != optimize::Outcome::Status::optimal || other.solution.cost < outcome.solution.cost))
          outcome = std::move(other);
      }
      std::string list;
      for (std::size_t k = 0; k < found.size(); ++k) list += (k ? ", " : "") + found[k];
      std::cout << "  costs found from " << options->starts << " starts: " << list
                << " (\"none\": no optimum from that start); the lowest is kept\n";
    }
    const optimize::HermiteSimpson& last = *outcome.problem;
    const optimize::Solution& solution = outcome.solution;

    using Status = optimize::Solution::Status;
    const std::string path_error =
        outcome.measured
            ? fmt::format(
                  "path error = {:.3g} ({}: {}; the local error is largest in interval {} of {}, [{:.6g}, {:.6g}])",
                  outcome.error.error, outcome.error.measure, outcome.error.where, outcome.error.interval + 1,
                  last.intervals(), outcome.error.t_low, outcome.error.t_high)
            : std::string();
    auto write = [&] {
      if (!options->output.empty()) {
        write_file_atomically(options->output, [&](std::ostream& out) { write_path(out, last, solution.z); });
        std::cout << "  wrote " << options->output << " (" << last.points() << " rows)\n";
      }
      if (!options->plot.empty()) {
        const std::string summary =
            outcome.status == optimize::Outcome::Status::optimal
                ? fmt::format("Cost {:.15g} (a local optimum), constraint violation {:.3g}, {}.", solution.cost,
                              solution.violation, path_error)
                : fmt::format("Not an optimum: {} ({} iterations); the last point, cost {:.10g}.", solution.words,
                              solution.iterations, solution.cost);
        write_plots(options->plot, scene, last, solution.z, {options->scene_path, options->guess}, summary);
        std::cout << "  wrote " << options->plot << "/plots.md\n";
      }
    };
    if (outcome.status == optimize::Outcome::Status::optimal) {
      std::cout << fmt::format("  cost = {:.15g}\n", solution.cost);
      if (settings.free_time()) std::cout << fmt::format("  t_end = {:.15g}\n", last.final_time(solution.z.data()));
      std::cout << fmt::format("  constraint violation = {:.3g}\n", solution.violation);
      std::cout << "  " << path_error << "\n";
      std::cout << "  intervals = " << last.intervals() << (last.intervals() != problem.intervals() ? " (refined)" : "")
                << "\n";
      std::cout << "  iterations = " << solution.iterations << "\n";
      if (solution.status == Status::acceptable)
        std::cout << "  IPOPT stopped at its acceptable level (1e-6) twice; the path error above meets the tolerance\n";
      std::cout
          << "  the optimum is local: IPOPT finds a point where no small change improves the cost; another start may "
             "find a lower one (--starts)\n";
      write();
      return kExitOk;
    }
    if (outcome.status == optimize::Outcome::Status::path_error) {
      std::cerr << "nhc: error: optimize: not an optimum of the continuous problem: " << outcome.words << "\n";
      return kExitMathFailure;
    }
    const std::string worst = solution.violation > 0 ? fmt::format("; the largest violation, {:.3g}, is in {}",
                                                                   solution.violation, solution.worst)
                                                     : "";
    if (solution.status == Status::iteration_limit) {
      write();
      std::cerr << "nhc: error: optimize: " << solution.words << " (" << solution.iterations << " iterations) at cost "
                << fmt::format("{:.10g}", solution.cost) << worst
                << (options->output.empty() ? "" : "; the last point is in " + options->output) << "\n";
      return kExitMathFailure;
    }
    if (solution.status == Status::infeasible)
      std::cerr << "nhc: error: optimize: no path meets the conditions: " << solution.words << worst << "\n";
    else std::cerr << "nhc: error: optimize: " << solution.words << worst << "\n";
    return kExitMathFailure;
  };
}

}  // namespace nhc::cli
