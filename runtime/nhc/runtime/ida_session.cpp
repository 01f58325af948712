#include "nhc/runtime/ida_session.hpp"

#include <idas/idas_ls.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "nhc/base/number_text.hpp"
#include "nhc/base/primed_name.hpp"

namespace nhc::runtime::ida_session {

void configure(void* ida, const IntegratorOptions& options, N_Vector id, const Check& check) {
  check(IDASStolerances(ida, options.rtol, options.atol), "setting the tolerances");
  check(IDASetId(ida, id), "setting the id vector");
  check(IDASetMaxNumSteps(ida, std::max(1L, options.max_steps)), "setting the step limit");
  // The algebraic states of the index-1 form are multipliers fixed by the differential states;
  // in the error test they only add noise (a stiff spring amplifies rounding in λ by K and
  // forces one failed step per step, docs/stability.md), so by default they are left out.
  check(IDASetSuppressAlg(ida, options.algebraic_in_error_test ? SUNFALSE : SUNTRUE),
        "excluding the algebraic states from the error test");
  if (options.max_step > 0) check(IDASetMaxStep(ida, options.max_step), "setting the maximum step");
  if (options.initial_step > 0) check(IDASetInitStep(ida, options.initial_step), "setting the initial step");
}

LinearSystem attach_linear_solver(void* ida, const Model& model, LinearSolverKind kind, N_Vector y, SUNContext ctx,
                                  IDALsJacFn jacobian, const Check& check) {
  LinearSystem ls;
  const long n = model.n_states();
  ls.sparse = uses_sparse_solver(model, kind);
  if (ls.sparse) {
    ls.A = sun::Matrix::sparse_csc(n, n, model.table().jacobian_nnz, ctx);
    ls.solver = sun::LinearSolver::klu(y, ls.A, ctx);
    ls.jacobian_kind = "generated sparse";
  } else {
    ls.A = sun::Matrix::dense(n, n, ctx);
    ls.solver = sun::LinearSolver::dense(y, ls.A, ctx);
    ls.jacobian_kind = model.has_dense_jacobian()    ? "generated dense"
                       : model.has_sparse_jacobian() ? "generated sparse (scattered)"
                                                     : "difference quotients";
  }
  check(IDASetLinearSolver(ida, ls.solver, ls.A), "attaching the linear solver");
  if (ls.sparse || model.has_dense_jacobian() || model.has_sparse_jacobian())
    check(IDASetJacFn(ida, jacobian), "setting the Jacobian function");
  return ls;
}

long fill_jacobian(const Model& model, bool sparse, double t, const double* y, const double* yp, double cj,
                   const double* p, SUNMatrix J) {
  const auto& tab = model.table();
  const int n = model.n_states();
  double* values = nullptr;
  long count = 0;
  if (sparse) {
    sunindextype* colptr = SUNSparseMatrix_IndexPointers(J);
    sunindextype* rowind = SUNSparseMatrix_IndexValues(J);
    for (int j = 0; j <= n; ++j) colptr[j] = tab.jacobian_colptr[j];
    for (int k = 0; k < tab.jacobian_nnz; ++k) rowind[k] = tab.jacobian_rowind[k];
    values = SUNSparseMatrix_Data(J);
    count = tab.jacobian_nnz;
    tab.jacobian_values(t, y, yp, cj, p, values);
  } else {
    values = SUNDenseMatrix_Data(J);
    count = static_cast<long>(n) * n;
    model.dense_jacobian(t, y, yp, cj, p, values);
  }
  for (long k = 0; k < count; ++k)
    if (!std::isfinite(values[k])) return k;
  return -1;
}

Statistics counters(void* ida, bool roots) {
  Statistics st;
  long v = 0;
  IDAGetNumSteps(ida, &st.steps);
  IDAGetNumResEvals(ida, &st.residual_evaluations);
  if (IDAGetNumLinResEvals(ida, &v) == IDA_SUCCESS) st.residual_evaluations += v;
  IDAGetNumJacEvals(ida, &st.jacobian_evaluations);
  IDAGetNumLinSolvSetups(ida, &st.linear_solver_setups);
  IDAGetNumErrTestFails(ida, &st.error_test_failures);
  IDAGetNumNonlinSolvIters(ida, &st.nonlinear_iterations);
  IDAGetNumNonlinSolvConvFails(ida, &st.nonlinear_failures);
  if (roots) IDAGetNumGEvals(ida, &st.root_evaluations);
  return st;
}

std::vector<int> root_monitors(const Model& model) {
  std::vector<int> roots;
  for (int k = 0; k < model.n_singular(); ++k)
    if (!model.euler_angles(k)) roots.push_back(k);
  return roots;
}

std::optional<base::SolverError> euler_angles_failure(const Model& model, double t, const double* y, const double* p,
                                                      const std::string& cause) {
  const int ns = model.n_singular();
  if (ns == 0 || !y) return std::nullopt;
  std::vector<double> s(static_cast<std::size_t>(ns));
  model.table().singular_quantities(t, y, p, s.data());
  std::optional<EulerAnglesMonitor> closest;
  double smallest = kEulerAnglesNear;
  for (int k = 0; k < ns; ++k) {
    std::optional<EulerAnglesMonitor> m = model.euler_angles(k);
    if (!m || !(std::abs(s[static_cast<std::size_t>(k)]) < smallest)) continue;
    smallest = std::abs(s[static_cast<std::size_t>(k)]);
    closest = std::move(m);
  }
  if (!closest) return std::nullopt;
  const EulerAnglesMonitor& m = *closest;
  const std::string& angle = m.angles[1];
  std::ostringstream os;
  os << "the " << m.axes << " Euler angles " << m.angles[0] << ", " << angle << ", " << m.angles[2]
     << " are close to their singularity at t = " << base::number_text(t, 15) << ": ";
  if (m.state >= 0) os << angle << " = " << base::number_text(y[m.state], 6);
  else os << angle << " is at " << m.zeros;
  os << " (" << m.axes << " angles are singular at " << angle << " = " << m.zeros
     << ": there the angular velocity does not determine the rates " << base::primed_name(m.angles[0], 1) << ", "
     << base::primed_name(angle, 1) << ", " << base::primed_name(m.angles[2], 1)
     << "); write the attitude with quat(q0, q1, q2, q3) and the constraint q0^2 + q1^2 + q2^2 + q3^2 = 1 "
        "instead (docs/quaternions.md). The solver: "
     << cause;
  return base::SolverError(base::FailureKind::singular_iteration_matrix, t, os.str());
}

}  // namespace nhc::runtime::ida_session
