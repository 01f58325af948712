#include "nhc/runtime/sundials.hpp"

#include <sundials/sundials_math.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <cmath>
#include <limits>
#include <new>
#include <sstream>

#include "nhc/base/number_text.hpp"

namespace nhc::runtime {

namespace sun {

std::string describe_ida_flag(int flag) {
  switch (flag) {
    case IDA_TOO_MUCH_WORK:
      return "the maximum number of internal steps was taken before reaching the output time";
    case IDA_TOO_MUCH_ACC:
      return "the requested accuracy cannot be reached (tolerances too small)";
    case IDA_ERR_FAIL:
      return "the local error test failed repeatedly or with the minimum step size";
    case IDA_CONV_FAIL:
      return "the Newton corrector failed to converge repeatedly or with the minimum step size";
    case IDA_LINIT_FAIL:
      return "the linear solver could not be initialised";
    case IDA_LSETUP_FAIL:
      return "the linear solver set-up (factorisation of the iteration matrix) failed unrecoverably";
    case IDA_LSOLVE_FAIL:
      return "the linear solve failed unrecoverably";
    case IDA_RES_FAIL:
      return "the residual function failed unrecoverably";
    case IDA_REP_RES_ERR:
      return "the residual function failed repeatedly";
    case IDA_RTFUNC_FAIL:
      return "the root (event) function failed";
    case IDA_CONSTR_FAIL:
      return "the inequality constraints could not be met";
    case IDA_FIRST_RES_FAIL:
      return "the residual function failed at the first call of the initial-condition calculation";
    case IDA_LINESEARCH_FAIL:
      return "the line search of the initial-condition calculation failed";
    case IDA_NO_RECOVERY:
      return "the residual, Jacobian or linear solver failed recoverably but could not recover";
    case IDA_NLS_INIT_FAIL:
      return "the nonlinear solver could not be initialised";
    case IDA_NLS_SETUP_FAIL:
      return "the nonlinear solver set-up failed";
    case IDA_NLS_FAIL:
      return "the nonlinear solver failed";
    case IDA_MEM_NULL:
      return "the integrator memory is null";
    case IDA_MEM_FAIL:
      return "out of memory";
    case IDA_ILL_INPUT:
      return "an input to the integrator is illegal";
    case IDA_NO_MALLOC:
      return "the integrator was not initialised";
    case IDA_BAD_EWT:
      return "an error weight became zero or negative (a state is zero with atol = 0?)";
    case IDA_BAD_K:
      return "illegal derivative order requested";
    case IDA_BAD_T:
      return "time outside the last step";
    case IDA_BAD_DKY:
      return "output vector is null";
    case IDA_VECTOROP_ERR:
      return "a vector operation failed";
    case IDA_CONTEXT_ERR:
      return "the SUNDIALS context is invalid";
    default:
      break;
  }
  std::ostringstream os;
  os << "SUNDIALS return code " << flag;
  return os.str();
}

base::FailureKind classify_ida_flag(int flag) {
  switch (flag) {
    case IDA_TOO_MUCH_WORK:
      return base::FailureKind::too_many_steps;
    case IDA_ERR_FAIL:
      return base::FailureKind::error_test;
    case IDA_CONV_FAIL:
    case IDA_NLS_FAIL:
    case IDA_LINESEARCH_FAIL:
    case IDA_NO_RECOVERY:
      return base::FailureKind::convergence;
    case IDA_LSETUP_FAIL:
    case IDA_LSOLVE_FAIL:
      return base::FailureKind::singular_iteration_matrix;
    case IDA_RES_FAIL:
    case IDA_REP_RES_ERR:
    case IDA_FIRST_RES_FAIL:
      return base::FailureKind::nonfinite_residual;
    case IDA_MEM_NULL:
    case IDA_MEM_FAIL:
    case IDA_ILL_INPUT:
    case IDA_NO_MALLOC:
    case IDA_LINIT_FAIL:
    case IDA_NLS_INIT_FAIL:
    case IDA_CONTEXT_ERR:
      return base::FailureKind::setup;
    default:
      return base::FailureKind::other;
  }
}

void check(int flag, const char* what, double t, const std::string& detail) {
  if (flag >= 0) return;
  std::string message = std::string(what) + " failed";
  if (!std::isnan(t)) message += " at t = " + base::number_text(t, 17);
  message += ": " + describe_ida_flag(flag);
  if (!detail.empty()) message += " (" + detail + ")";
  throw base::SolverError(classify_ida_flag(flag), t, message);
}

namespace {
template <class T>
T require(T handle, const char* what) {
  if (!handle) throw base::SolverError(base::FailureKind::setup, base::kNoTime, std::string("cannot create ") + what);
  return handle;
}

/// SUNDIALS' N_VClone writes into the clone it gets without checking it (6.x: result->sunctx),
/// so a clone the C library could not allocate crashed the process inside IDA (IDASetId under
/// `ulimit -v`). Every vector nhc makes clones through this: an allocation failure is
/// std::bad_alloc, which each front end reports as out of memory (exit 4); the C frames it
/// crosses carry unwind tables (x86-64), and what IDA allocated before is lost with the failure.
N_Vector checked_clone(N_Vector w) {
  N_Vector v = N_VClone_Serial(w);
  if (!v) throw std::bad_alloc();
  return v;
}
}  // namespace

Context Context::create() {
  SUNContext ctx = nullptr;
  if (SUNContext_Create(nullptr, &ctx) != 0 || !ctx)
    throw base::SolverError(base::FailureKind::setup, base::kNoTime, "cannot create the SUNDIALS context");
  return Context(ctx);
}

Vector Vector::create(long length, SUNContext ctx) {
  N_Vector v = require(N_VNew_Serial(length, ctx), "a SUNDIALS vector");
  v->ops->nvclone = &checked_clone;  // clones copy the operations table
  return Vector(v);
}

long Vector::size() const noexcept { return static_cast<long>(N_VGetLength(get())); }

Matrix Matrix::dense(long rows, long cols, SUNContext ctx) {
  return Matrix(require(SUNDenseMatrix(rows, cols, ctx), "a dense SUNDIALS matrix"));
}

Matrix Matrix::sparse_csc(long rows, long cols, long nnz, SUNContext ctx) {
  return Matrix(require(SUNSparseMatrix(rows, cols, nnz, CSC_MAT, ctx), "a sparse SUNDIALS matrix"));
}

LinearSolver LinearSolver::dense(N_Vector y, SUNMatrix A, SUNContext ctx) {
  return LinearSolver(require(SUNLinSol_Dense(y, A, ctx), "the dense linear solver"));
}

LinearSolver LinearSolver::klu(N_Vector y, SUNMatrix A, SUNContext ctx) {
  return LinearSolver(require(SUNLinSol_KLU(y, A, ctx), "the KLU sparse linear solver"));
}

IdaMemory IdaMemory::create(SUNContext ctx) { return IdaMemory(require(IDACreate(ctx), "the IDA integrator")); }

namespace {

thread_local CloneRecorder* active_recorder = nullptr;
thread_local std::vector<N_Vector>* active_clones = nullptr;

N_Vector recording_clone(N_Vector w) {
  N_Vector v = checked_clone(w);
  if (active_clones) {
    const sunindextype n = N_VGetLength_Serial(v);
    double* data = N_VGetArrayPointer_Serial(v);
    for (sunindextype i = 0; i < n; ++i) data[i] = std::numeric_limits<double>::quiet_NaN();
    active_clones->push_back(v);
  }
  return v;
}

bool equal(N_Vector a, N_Vector b) {
  const sunindextype n = N_VGetLength_Serial(a);
  if (N_VGetLength_Serial(b) != n) return false;
  const double* x = N_VGetArrayPointer_Serial(a);
  const double* y = N_VGetArrayPointer_Serial(b);
  for (sunindextype i = 0; i < n; ++i)
    if (!(x[i] == y[i])) return false;
  return true;
}

}  // namespace

CloneRecorder::CloneRecorder(N_Vector y) : previous_(active_recorder) {
  y->ops->nvclone = &recording_clone;  // clones copy the operations table, so they record too
  active_recorder = this;
  active_clones = &clones_;
}

CloneRecorder::~CloneRecorder() {
  active_recorder = previous_;
  active_clones = previous_ ? &previous_->clones_ : nullptr;
}

N_Vector find_solution_history(const std::vector<N_Vector>& clones, N_Vector y0, N_Vector yp0) {
  N_Vector found = nullptr;
  for (std::size_t k = 0; k + 1 < clones.size(); ++k)
    if (equal(clones[k], y0) && equal(clones[k + 1], yp0)) {
      if (found) return nullptr;  // ambiguous: do not guess
      found = clones[k];
    }
  return found;
}

}  // namespace sun
}  // namespace nhc::runtime
