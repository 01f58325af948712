#pragma once
/// \file sundials.hpp
/// \brief Move-only RAII owners of the SUNDIALS objects the runtime uses, and the one place
/// where SUNDIALS return codes are checked and turned into SolverError
/// (cf. sundials/sundials_context.hpp).

#include <idas/idas.h>  // IDAS: IDA with forward sensitivities (one library, a superset of IDA)
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>

#include <string>
#include <utility>
#include <vector>

#include "nhc/base/errors.hpp"

namespace nhc::runtime::sun {

/// Throws SolverError when `flag` < 0: "`what` failed at t = T: <meaning of flag>[: detail]".
/// `detail` is typically the message SUNDIALS passed to the error handler.
void check(int flag, const char* what, double t = base::kNoTime, const std::string& detail = {});

/// The meaning of an IDA return flag in words ("the corrector did not converge ...").
std::string describe_ida_flag(int flag);

/// The failure kind of an IDA return flag.
base::FailureKind classify_ida_flag(int flag);

/// A move-only owner of a pointer-like SUNDIALS handle; Traits::destroy(h) frees it.
template <class Handle, class Traits>
class Owner {
 public:
  Owner() = default;
  explicit Owner(Handle h) : handle_(h) {}
  ~Owner() { reset(); }
  Owner(const Owner&) = delete;
  Owner& operator=(const Owner&) = delete;
  Owner(Owner&& other) noexcept : handle_(std::exchange(other.handle_, Handle{})) {}
  Owner& operator=(Owner&& other) noexcept {
    if (this != &other) {
      reset();
      handle_ = std::exchange(other.handle_, Handle{});
    }
    return *this;
  }
  Handle get() const noexcept { return handle_; }
  operator Handle() const noexcept { return handle_; }  // NOLINT: pass straight to C API
  explicit operator bool() const noexcept { return handle_ != Handle{}; }
  void reset() noexcept {
    if (handle_ != Handle{}) Traits::destroy(handle_);
    handle_ = Handle{};
  }
  Handle release() noexcept { return std::exchange(handle_, Handle{}); }

 private:
  Handle handle_{};
};

struct ContextTraits {
  static void destroy(SUNContext c) noexcept { SUNContext_Free(&c); }
};
struct VectorTraits {
  static void destroy(N_Vector v) noexcept { N_VDestroy(v); }
};
struct MatrixTraits {
  static void destroy(SUNMatrix m) noexcept { SUNMatDestroy(m); }
};
struct LinearSolverTraits {
  static void destroy(SUNLinearSolver s) noexcept { SUNLinSolFree(s); }
};
struct IdaTraits {
  static void destroy(void* mem) noexcept { IDAFree(&mem); }
};

/// SUNContext (one per integrator).
class Context : public Owner<SUNContext, ContextTraits> {
 public:
  Context() = default;
  using Owner::Owner;  ///< adopts a handle
  static Context create();
};

/// A serial N_Vector.
class Vector : public Owner<N_Vector, VectorTraits> {
 public:
  Vector() = default;
  using Owner::Owner;  ///< adopts a handle
  static Vector create(long length, SUNContext ctx);
  double* data() const noexcept { return N_VGetArrayPointer(get()); }
  long size() const noexcept;
  double& operator[](long i) const noexcept { return data()[i]; }
};

/// A SUNMatrix: dense, or compressed-sparse-column.
class Matrix : public Owner<SUNMatrix, MatrixTraits> {
 public:
  Matrix() = default;
  using Owner::Owner;  ///< adopts a handle
  static Matrix dense(long rows, long cols, SUNContext ctx);
  static Matrix sparse_csc(long rows, long cols, long nnz, SUNContext ctx);
};

/// A SUNLinearSolver: dense LU or KLU.
class LinearSolver : public Owner<SUNLinearSolver, LinearSolverTraits> {
 public:
  LinearSolver() = default;
  using Owner::Owner;  ///< adopts a handle
  static LinearSolver dense(N_Vector y, SUNMatrix A, SUNContext ctx);
  static LinearSolver klu(N_Vector y, SUNMatrix A, SUNContext ctx);
};

/// IDA's integrator memory.
class IdaMemory : public Owner<void*, IdaTraits> {
 public:
  IdaMemory() = default;
  using Owner::Owner;  ///< adopts a handle
  static IdaMemory create(SUNContext ctx);
};

/// Records the vectors IDA(S) clones from `y` while it lives (IDAInit allocates its work space
/// so), each filled with NaN first. With it, IDA's divided difference phi[0] (the current
/// solution y_n) is found without IDA's private header: IDAInit copies y0 and y'0 into phi[0]
/// and phi[1], allocated one after the other, and into no other vector (find_solution_history).
class CloneRecorder {
 public:
  explicit CloneRecorder(N_Vector y);
  ~CloneRecorder();
  CloneRecorder(const CloneRecorder&) = delete;
  CloneRecorder& operator=(const CloneRecorder&) = delete;
  const std::vector<N_Vector>& clones() const noexcept { return clones_; }

 private:
  std::vector<N_Vector> clones_;
  CloneRecorder* previous_ = nullptr;
};

/// IDA's phi[0] among `clones` (recorded around IDAInit(…, y0, yp0)): the first of two
/// consecutive clones equal to y0 and yp0; null when there is no such unique pair.
N_Vector find_solution_history(const std::vector<N_Vector>& clones, N_Vector y0, N_Vector yp0);

}  // namespace nhc::runtime::sun
