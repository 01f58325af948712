#pragma once
/// \file ida_session.hpp
/// \brief What a plain run (integrator.cpp) and a run with sensitivities (sensitivity.cpp) set up
/// in IDA(S) the same way, in one place: the options every run takes from IntegratorOptions, the
/// linear solver and Jacobian, the Jacobian callback's values, and IDA's counters. The starting
/// point is the other shared rule (solve_starting_point, hidden_constraints.hpp).

#include <idas/idas.h>

#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "nhc/runtime/integrator.hpp"
#include "nhc/runtime/model.hpp"
#include "nhc/runtime/sundials.hpp"

namespace nhc::runtime::ida_session {

/// Checks a SUNDIALS return flag, naming the step in the message (the caller's check()).
using Check = std::function<void(int flag, const char* what)>;

/// Tolerances, the id vector, the step limit, the algebraic states left out of the error test
/// unless asked, the largest and the first step.
void configure(void* ida, const IntegratorOptions& options, N_Vector id, const Check& check);

/// The linear solver of `kind` for `model` (uses_sparse_solver), attached to `ida` with
/// `jacobian` as its Jacobian function when the model carries one.
struct LinearSystem {
  sun::Matrix A;
  sun::LinearSolver solver;
  bool sparse = false;
  std::string jacobian_kind;  ///< Statistics::jacobian
};
LinearSystem attach_linear_solver(void* ida, const Model& model, LinearSolverKind kind, N_Vector y, SUNContext ctx,
                                  IDALsJacFn jacobian, const Check& check);

/// J = dF/dy + cj dF/dy' into IDA's matrix: the compressed columns (pattern and values) for
/// KLU, else dense (Model::dense_jacobian). Returns the index of the first entry that is not
/// finite (into the values, or column-major for dense), or -1.
long fill_jacobian(const Model& model, bool sparse, double t, const double* y, const double* yp, double cj,
                   const double* p, SUNMatrix J);

/// The monitors IDA watches as root functions (Model::n_singular's indices): all but the Euler
/// angles' (Model::euler_angles), whose zeros a scene may pass through; they only explain a failure.
std::vector<int> root_monitors(const Model& model);

/// An Euler-angle monitor (sin or cos of the middle angle, the middle angle within about 5.7° of
/// where they are singular) below this at the last accepted point of a failed run names the angle
/// as the cause. Near there the outer angles' rates grow as 1/monitor and their accelerations as
/// its square; the runs that fail there stop with it between 0.002 and 0.035 (balls on a
/// turntable, docs/quaternions.md), so a tighter bound would miss some.
inline constexpr double kEulerAnglesNear = 0.1;

/// When a run that failed (at its start or later; `cause` in the solver's words) was, at its last
/// accepted point (t, y; parameters and inputs p), within kEulerAnglesNear of a singularity of its
/// Euler angles: the error that names the angle and its value and points to quat()
/// (docs/quaternions.md), the closest such monitor's. Else nothing.
std::optional<base::SolverError> euler_angles_failure(const Model& model, double t, const double* y, const double* p,
                                                      const std::string& cause);

/// IDA's counters since its last (re)initialization; the root evaluations when `roots`.
Statistics counters(void* ida, bool roots);

/// Adds the seconds from its construction to its end to `total` (Statistics' timings).
class Stopwatch {
 public:
  explicit Stopwatch(double& total) : total_(total), start_(std::chrono::steady_clock::now()) {}
  ~Stopwatch() { total_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
  Stopwatch(const Stopwatch&) = delete;
  Stopwatch& operator=(const Stopwatch&) = delete;

 private:
  double& total_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace nhc::runtime::ida_session
