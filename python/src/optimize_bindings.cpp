#include "optimize_bindings.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <vector>

#include "nhc/app/optimize_options.hpp"
#include "nhc/app/optimize_request.hpp"
#include "nhc/errors.hpp"
#include "nhc/io/csv_file.hpp"
#include "nhc/optimize/hermite_simpson.hpp"
#include "nhc/optimize/path_table.hpp"
#include "nhc/optimize/refine.hpp"
#include "nhc/optimize/settings.hpp"
#include "nhc/optimize/solve.hpp"
#include "nhc/scene/scene.hpp"
#include "symbolic_work.hpp"

namespace py = pybind11;

namespace nhc::python {

namespace {

const char* status_name(optimize::Solution::Status s) {
  switch (s) {
    case optimize::Solution::Status::optimal:
      return "optimal";
    case optimize::Solution::Status::iteration_limit:
      return "iteration_limit";
    case optimize::Solution::Status::acceptable:
      return "acceptable";
    case optimize::Solution::Status::infeasible:
      return "infeasible";
    default:
      return "failed";
  }
}

py::dict optimize_scene(const Scene& scene, std::optional<long long> intervals, long long max_iterations,
                        double tolerance, const std::string& jacobian, const std::string& hessian,
                        double path_tolerance, const std::optional<std::vector<std::string>>& guess_columns,
                        const std::optional<std::vector<std::vector<double>>>& guess_rows,
                        const std::string& guess_name, const std::string& guess_file) {
  const app::OptimizeRequest request{intervals, max_iterations, tolerance, jacobian, hessian, path_tolerance};
  app::check_optimize_request(request, app::optimize_python_names());
  // Reading, deriving and reducing: symbolic work.
  std::optional<optimize::HermiteSimpson> problem;
  const optimize::Settings settings = symbolic_work([&] { return optimize::read_settings(scene); });
  symbolic_work([&] {
    problem.emplace(scene, settings, static_cast<int>(request.intervals.value_or(settings.intervals)));
    return 0;
  });
  std::vector<double> guess;
  if (!guess_file.empty()) {
    // The command line's reader and rules (nhc/io/csv_file.hpp).
    const CsvFile file = read_csv_file(guess_file, "a CSV file for guess");
    guess = optimize::guess_from_table(*problem, file.header, file.numbers(), scene, "guess", guess_file);
  } else if (guess_columns) {
    if (!guess_rows) throw InputError({"guess", 0, 0}, "guess: columns without rows");
    guess = optimize::guess_from_table(*problem, *guess_columns, *guess_rows, scene, "guess", guess_name);
  }
  optimize::SolveOptions options = app::solve_options(request);
  bool interrupted = false;
  options.progress = [&](int, double, double) {
    py::gil_scoped_acquire gil;  // the solve runs without the GIL; signals are Python's
    if (PyErr_CheckSignals() != 0) interrupted = true;
    return !interrupted;
  };
  optimize::RefineOptions refine = app::refine_options(request, problem->intervals());
  std::vector<std::string> rounds;
  refine.report = [&](const std::string& line) { rounds.push_back(line); };
  std::optional<optimize::Outcome> outcome;
  {
    // Other Python threads run during the solve (IPOPT and the replay touch no Python object).
    py::gil_scoped_release release;
    outcome.emplace(optimize::solve_refined(*problem, guess, options, refine));
  }
  if (interrupted) throw py::error_already_set();
  const optimize::Solution& solution = outcome->solution;
  problem.emplace(*outcome->problem);

  const std::vector<std::string> columns = optimize::path_columns(*problem);
  const std::vector<std::vector<double>> rows = optimize::path_rows(*problem, solution.z);
  py::array_t<double> data({rows.size(), columns.size()});
  auto cells = data.mutable_unchecked<2>();
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (std::size_t c = 0; c < columns.size(); ++c)
      cells(static_cast<py::ssize_t>(r), static_cast<py::ssize_t>(c)) = rows[r][c];
  py::dict summary;
  summary["cost"] = solution.cost;
  summary["violation"] = solution.violation;
  summary["worst_constraint"] = solution.worst;
  summary["iterations"] = solution.iterations;
  const bool path_error = outcome->status == optimize::Outcome::Status::path_error;
  summary["status"] = outcome->status == optimize::Outcome::Status::optimal ? std::string("optimal")
                      : path_error                                          ? std::string("path_error")
                                                                            : std::string(status_name(solution.status));
  summary["words"] = path_error ? "not an optimum of the continuous problem: " + outcome->words : solution.words;
  summary["solver_status"] = status_name(solution.status);
  summary["rounds"] = rounds;
  summary["local"] = true;  // IPOPT's optimum is local
  if (outcome->measured) {
    summary["path_error"] = outcome->error.error;
    summary["path_error_measure"] = outcome->error.measure;
    summary["path_error_where"] = outcome->error.where;
    summary["path_error_interval"] = py::make_tuple(outcome->error.t_low, outcome->error.t_high);
  } else {
    summary["path_error"] = py::none();
  }
  summary["t_end"] = problem->final_time(solution.z.data());
  summary["intervals"] = problem->intervals();
  summary["variables"] = problem->variables();
  summary["constraints"] = problem->constraints();
  summary["problem"] = problem->inputs() ? to_string(problem->point_problem().model) : std::string("vakonomic");
  py::dict out;
  out["columns"] = columns;
  out["data"] = data;
  out["summary"] = summary;
  return out;
}

}  // namespace

void register_optimize(py::module_& m) {
  m.def("_optimize", &optimize_scene, py::arg("scene"), py::arg("intervals"), py::arg("max_iterations"),
        py::arg("tolerance"), py::arg("jacobian"), py::arg("hessian"), py::arg("path_tolerance"),
        py::arg("guess_columns"), py::arg("guess_rows"), py::arg("guess_name"), py::arg("guess_file") = std::string());
}

}  // namespace nhc::python
