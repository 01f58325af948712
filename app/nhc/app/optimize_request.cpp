#include "nhc/app/optimize_request.hpp"

#include "nhc/app/run_request.hpp"
#include "nhc/errors.hpp"

namespace nhc::app {

namespace {

[[noreturn]] void refuse_optimize(const std::string& field, const std::string& message) {
  throw InputError({field, 0, 0}, message);
}

void check_count(const std::string& field, long long value, long long low, long long high) {
  if (const std::string why = count_problem(value, low, high); !why.empty())
    refuse_optimize(field, field + ": " + std::to_string(value) + " " + why);
}

void check_choice(const std::string& field, const std::string& value, const std::string& a, const std::string& b) {
  if (value != a && value != b) refuse_optimize(field, field + ": '" + value + "' is neither " + a + " nor " + b);
}

}  // namespace

const OptimizeFieldNames& optimize_command_line_names() {
  static const OptimizeFieldNames names{"--intervals", "--max-iterations", "--tolerance",
                                        "--jacobian",  "--hessian",        "--path-tolerance"};
  return names;
}

const OptimizeFieldNames& optimize_python_names() {
  static const OptimizeFieldNames names{"intervals", "max_iterations", "tolerance",
                                        "jacobian",  "hessian",        "path_tolerance"};
  return names;
}

void check_optimize_request(const OptimizeRequest& r, const OptimizeFieldNames& names) {
  if (r.intervals) check_count(names.intervals, *r.intervals, 1, kMaxIntervals);
  check_count(names.max_iterations, r.max_iterations, 1, kMaxIterations);
  if (const std::string why = positive_problem(r.tolerance); !why.empty())
    refuse_optimize(names.tolerance, names.tolerance + ": " + std::to_string(r.tolerance) + " " + why);
  if (const std::string why = positive_problem(r.path_tolerance); !why.empty())
    refuse_optimize(names.path_tolerance, names.path_tolerance + ": " + std::to_string(r.path_tolerance) + " " + why);
  check_choice(names.jacobian, r.jacobian, "exact", "finite-differences");
  check_choice(names.hessian, r.hessian, "exact", "limited-memory");
}

OptimizeChoices optimize_choices(const OptimizeRequest& r) {
  OptimizeChoices c;
  c.max_iterations = static_cast<int>(r.max_iterations);
  c.tolerance = r.tolerance;
  c.jacobian = r.jacobian == "finite-differences" ? JacobianChoice::finite_differences : JacobianChoice::exact;
  c.hessian = r.hessian == "limited-memory" ? HessianChoice::limited_memory : HessianChoice::exact;
  c.path_tolerance = r.path_tolerance;
  return c;
}

}  // namespace nhc::app
