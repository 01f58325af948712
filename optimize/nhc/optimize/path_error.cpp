#include "nhc/optimize/path_error.hpp"

#include <fmt/format.h>
#include <idas/idas.h>
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "nhc/errors.hpp"
#include "nhc/runtime/sundials.hpp"

namespace nhc::optimize {

namespace {

constexpr int kPathRowOffset = 2;  // PathFunctions: the integrand, the final cost, then the path rows
constexpr double kReplayTolerance = 1e-10;
constexpr long kMaxSteps = 200000;

/// The transcription's interpolant at fraction sigma of interval k: each differential state the
/// cubic Hermite polynomial through its values and rates at the interval's ends (its rate that
/// cubic's derivative), an algebraic state and each input the quadratic through the interval's
/// three points (an algebraic state's rate 0).
void interpolate(const HermiteSimpson& p, const double* z, int k, double sigma, std::vector<double>& point) {
  const PointProblem& problem = p.point_problem();
  const int a = 2 * k, m = a + 1, b = a + 2, n = problem.states;
  const double h = p.interval_length(k, z), s = sigma, s2 = s * s, s3 = s2 * s;
  const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
  const double d00 = 6 * s2 - 6 * s, d10 = 3 * s2 - 4 * s + 1, d01 = -6 * s2 + 6 * s, d11 = 3 * s2 - 2 * s;
  const double la = 2 * (s - 0.5) * (s - 1), lm = -4 * s * (s - 1), lb = 2 * s * (s - 0.5);
  point.assign(static_cast<std::size_t>(problem.slots()), 0.0);
  for (int i = 0; i < n; ++i) {
    const double ya = z[p.q_index(a, i)], yb = z[p.q_index(b, i)];
    if (problem.collocated[static_cast<std::size_t>(i)]) {
      const double va = z[p.v_index(a, i)], vb = z[p.v_index(b, i)];
      point[static_cast<std::size_t>(i)] = h00 * ya + h * h10 * va + h01 * yb + h * h11 * vb;
      point[static_cast<std::size_t>(n + i)] = (d00 * ya + d01 * yb) / h + d10 * va + d11 * vb;
    } else {
      point[static_cast<std::size_t>(i)] = la * ya + lm * z[p.q_index(m, i)] + lb * yb;
    }
  }
  for (int u = 0; u < problem.inputs; ++u)
    point[static_cast<std::size_t>(2 * n + u)] =
        la * z[p.u_index(a, u)] + lm * z[p.u_index(m, u)] + lb * z[p.u_index(b, u)];
}

/// Per differential state, max(1, its largest |value| at the nodes); 0 for an algebraic state
/// (not compared).
std::vector<double> state_scales(const HermiteSimpson& p, const double* z) {
  const PointProblem& problem = p.point_problem();
  std::vector<double> scale(static_cast<std::size_t>(problem.states), 0.0);
  for (int i = 0; i < problem.states; ++i) {
    if (!problem.collocated[static_cast<std::size_t>(i)]) continue;
    double largest = 1;
    for (int j = 0; j < p.points(); j += 2) largest = std::max(largest, std::abs(z[p.q_index(j, i)]));
    scale[static_cast<std::size_t>(i)] = largest;
  }
  return scale;
}

void finish(PathError& out, const HermiteSimpson& p, const double* z) {
  out.interval = static_cast<int>(std::max_element(out.local.begin(), out.local.end()) - out.local.begin());
  out.t_low = p.time(2 * out.interval, z);
  out.t_high = p.time(2 * out.interval + 2, z);
}

PathError residual_error(HermiteSimpson& p, const std::vector<double>& zv) {
  const double* z = zv.data();
  const PointProblem& problem = p.point_problem();
  const std::vector<double> scale = state_scales(p, z);
  const double common = std::max(1.0, *std::max_element(scale.begin(), scale.end()));
  PathError out;
  out.measure = "quarter-point residuals";
  out.local.assign(static_cast<std::size_t>(p.intervals()), 0.0);
  std::vector<double> point;
  double largest = -1;
  for (int k = 0; k < p.intervals(); ++k) {
    const double h = p.interval_length(k, z);
    for (double sigma : {0.25, 0.75}) {
      interpolate(p, z, k, sigma, point);
      const double t = p.time(2 * k, z) + sigma * h;
      p.functions().evaluate_values(t, point.data());
      double e = 0;
      std::string what;
      for (std::size_t r = 0; r < problem.path.size(); ++r) {
        const PointRow& row = problem.path[r];
        const double g = p.functions().value(kPathRowOffset + static_cast<int>(r)).value;
        const double outside =
            std::isfinite(g) ? std::max({row.low - g, g - row.high, 0.0}) : std::numeric_limits<double>::infinity();
        if (!(outside * h / common <= e)) {
          e = outside * h / common;
          what = fmt::format("{} at t = {:.6g}", row.name, t);
        }
      }
      // A state's bound between the points (a variable bound holds at the points only).
      for (int i = 0; i < problem.states; ++i) {
        if (!problem.collocated[static_cast<std::size_t>(i)]) continue;
        const int index = p.q_index(2 * k + 1, i);
        const double y = point[static_cast<std::size_t>(i)];
        const double outside = std::max({p.variable_low(index) - y, y - p.variable_high(index), 0.0});
        if (outside / common > e) {
          e = outside / common;
          what = fmt::format("the bound on {} at t = {:.6g}", problem.state_names[static_cast<std::size_t>(i)], t);
        }
      }
      auto& local = out.local[static_cast<std::size_t>(k)];
      local = std::max(local, e);
      if (e > largest) {
        largest = e;
        out.where = what;
      }
    }
  }
  finish(out, p, z);
  out.error = out.local[static_cast<std::size_t>(out.interval)];
  return out;
}

// ---- the replay by IDA -------------------------------------------------------------------------

struct Replay {
  HermiteSimpson* p = nullptr;
  const double* z = nullptr;
  int interval = 0;
  std::vector<double> point;
  std::string failure;  ///< a non-finite residual, in words
};

void load(Replay& r, double t, N_Vector y, N_Vector yp) {
  const PointProblem& problem = r.p->point_problem();
  const double h = r.p->interval_length(r.interval, r.z);
  const double sigma = std::clamp((t - r.p->time(2 * r.interval, r.z)) / h, 0.0, 1.0);
  interpolate(*r.p, r.z, r.interval, sigma, r.point);  // the inputs' quadratic (the states overwritten)
  const double* yd = N_VGetArrayPointer(y);
  const double* ypd = N_VGetArrayPointer(yp);
  std::copy(yd, yd + problem.states, r.point.begin());
  std::copy(ypd, ypd + problem.states, r.point.begin() + problem.states);
}

int replay_residual(sunrealtype t, N_Vector y, N_Vector yp, N_Vector res, void* data) {
  Replay& r = *static_cast<Replay*>(data);
  load(r, t, y, yp);
  r.p->functions().evaluate_values(t, r.point.data());
  double* out = N_VGetArrayPointer(res);
  for (int row = 0; row < r.p->point_problem().dynamics_rows; ++row) {
    out[row] = r.p->functions().value(kPathRowOffset + row).value;
    if (!std::isfinite(out[row])) {
      r.failure = fmt::format("{} is not finite at t = {:.6g}",
                              r.p->point_problem().path[static_cast<std::size_t>(row)].name, t);
      return 1;
    }
  }
  return 0;
}

int replay_jacobian(sunrealtype t, sunrealtype cj, N_Vector y, N_Vector yp, N_Vector, SUNMatrix J, void* data, N_Vector,
                    N_Vector, N_Vector) {
  Replay& r = *static_cast<Replay*>(data);
  const int n = r.p->point_problem().states;
  load(r, t, y, yp);
  r.p->functions().evaluate(t, r.point.data());
  SUNMatZero(J);
  for (int row = 0; row < r.p->point_problem().dynamics_rows; ++row) {
    const ValueGradient& f = r.p->functions().value(kPathRowOffset + row);
    const std::vector<int>& slots = r.p->functions().slots(kPathRowOffset + row);
    for (std::size_t e = 0; e < slots.size(); ++e) {
      const int s = slots[e];
      if (!std::isfinite(f.d[e])) return 1;
      if (s < n) SM_ELEMENT_D(J, row, s) += f.d[e];
      else if (s < 2 * n) SM_ELEMENT_D(J, row, s - n) += cj * f.d[e];
    }
  }
  return 0;
}

/// One IDA integrator over the model's residual with the inputs of the current interval.
class ReplaySession {
 public:
  ReplaySession(HermiteSimpson& p, const double* z) {
    data_.p = &p;
    data_.z = z;
    n_ = p.point_problem().states;
    if (SUNContext_Create(nullptr, &context_) != 0) throw EnvironmentError("SUNDIALS could not create its context");
    y_ = N_VNew_Serial(n_, context_);
    yp_ = N_VNew_Serial(n_, context_);
    A_ = SUNDenseMatrix(n_, n_, context_);
    LS_ = SUNLinSol_Dense(y_, A_, context_);
    mem_ = IDACreate(context_);
    if (!y_ || !yp_ || !A_ || !LS_ || !mem_)
      throw EnvironmentError("SUNDIALS could not allocate the replay's integrator");
    set_node(0);
    check(IDAInit(mem_, replay_residual, p.time(0, z), y_, yp_), "IDAInit");
    check(IDASStolerances(mem_, kReplayTolerance, kReplayTolerance), "IDASStolerances");
    check(IDASetUserData(mem_, &data_), "IDASetUserData");
    check(IDASetLinearSolver(mem_, LS_, A_), "IDASetLinearSolver");
    check(IDASetJacFn(mem_, replay_jacobian), "IDASetJacFn");
    check(IDASetMaxNumSteps(mem_, kMaxSteps), "IDASetMaxNumSteps");
    // Failures are reported in words by the caller, not printed by SUNDIALS.
    check(IDASetErrHandlerFn(
              mem_, [](int, const char*, const char*, char*, void*) {}, nullptr),
          "IDASetErrHandlerFn");
    id_ = N_VNew_Serial(n_, context_);
    double* id = N_VGetArrayPointer(id_);
    for (int i = 0; i < n_; ++i) id[i] = p.point_problem().collocated[static_cast<std::size_t>(i)] ? 1.0 : 0.0;
    check(IDASetId(mem_, id_), "IDASetId");
  }
  ~ReplaySession() {
    if (mem_) IDAFree(&mem_);
    if (LS_) SUNLinSolFree(LS_);
    if (A_) SUNMatDestroy(A_);
    if (yp_) N_VDestroy(yp_);
    if (id_) N_VDestroy(id_);
    if (y_) N_VDestroy(y_);
    if (context_) SUNContext_Free(&context_);
  }
  ReplaySession(const ReplaySession&) = delete;
  ReplaySession& operator=(const ReplaySession&) = delete;

  /// Restarts at node k of the path (its states and rates).
  void restart(int k) {
    set_node(k);
    const double t = data_.p->time(2 * k, data_.z);
    check(IDAReInit(mem_, t, y_, yp_), "IDAReInit");
    // The path's state meets F only to the solver's tolerance: the algebraic states and the
    // rates are made consistent with the differential states (IDACalcIC), which are kept.
    data_.interval = std::min(k, data_.p->intervals() - 1);
    IDACalcIC(mem_, IDA_YA_YDP_INIT, data_.p->time(std::min(2 * k + 2, data_.p->points() - 1), data_.z));
    IDAGetConsistentIC(mem_, y_, yp_);
  }
  /// Integrates over interval k (from wherever the integrator is, at its first node); false with
  /// `failure` set when IDA stops.
  bool across(int k, std::string& failure) {
    data_.interval = k;
    const double t_end = data_.p->time(2 * k + 2, data_.z);
    IDASetStopTime(mem_, t_end);
    double t = 0;
    const int flag = IDASolve(mem_, t_end, &t, y_, yp_, IDA_NORMAL);
    if (flag < 0) {
      failure = fmt::format("IDA stopped at t = {:.6g}: {}", t,
                            data_.failure.empty() ? runtime::sun::describe_ida_flag(flag) : data_.failure);
      return false;
    }
    return true;
  }
  /// Largest |y_i - path's y_i at node| / scale_i.
  double deviation(int node, const std::vector<double>& scale) const {
    const double* y = N_VGetArrayPointer(y_);
    double e = 0;
    for (int i = 0; i < n_; ++i)
      if (scale[static_cast<std::size_t>(i)] > 0)
        e = std::max(e, std::abs(y[i] - data_.z[data_.p->q_index(2 * node, i)]) / scale[static_cast<std::size_t>(i)]);
    return e;
  }

 private:
  void set_node(int k) {
    double* y = N_VGetArrayPointer(y_);
    double* yp = N_VGetArrayPointer(yp_);
    for (int i = 0; i < n_; ++i) {
      y[i] = data_.z[data_.p->q_index(2 * k, i)];
      yp[i] = data_.z[data_.p->v_index(2 * k, i)];
    }
  }
  static void check(int flag, const char* what) {
    if (flag < 0)
      throw EnvironmentError(fmt::format("the replay's {} failed: {}", what, runtime::sun::describe_ida_flag(flag)));
  }

  Replay data_;
  int n_ = 0;
  SUNContext context_ = nullptr;
  N_Vector y_ = nullptr, yp_ = nullptr, id_ = nullptr;
  SUNMatrix A_ = nullptr;
  SUNLinearSolver LS_ = nullptr;
  void* mem_ = nullptr;
};

PathError replay_error(HermiteSimpson& p, const std::vector<double>& zv) {
  const double* z = zv.data();
  const std::vector<double> scale = state_scales(p, z);
  PathError out;
  out.measure = "replay by IDA";
  out.local.assign(static_cast<std::size_t>(p.intervals()), 0.0);
  ReplaySession session(p, z);
  // Local: each interval from its first node.
  std::string failure;
  for (int k = 0; k < p.intervals(); ++k) {
    session.restart(k);
    out.local[static_cast<std::size_t>(k)] =
        session.across(k, failure) ? session.deviation(k + 1, scale) : std::numeric_limits<double>::infinity();
  }
  finish(out, p, z);
  // Global: from the initial state through every interval.
  session.restart(0);
  int worst_node = 0;
  double global = 0;
  for (int k = 0; k < p.intervals(); ++k) {
    if (!session.across(k, failure)) {
      global = std::numeric_limits<double>::infinity();
      out.replay_failure = failure;
      break;
    }
    const double e = session.deviation(k + 1, scale);
    if (!(e <= global)) {
      global = e;
      worst_node = k + 1;
    }
  }
  out.replay = global;
  out.replay_at = p.time(2 * worst_node, z);
  double sum = 0;
  for (double e : out.local) sum += e;
  out.local_sum = sum;
  // The replay from t0 measures the path and the system's growth of small differences; where
  // that growth dominates (an unstable motion: the replay's deviation above the sum of the
  // intervals' own errors, which bounds it for a motion that does not amplify), the path is
  // judged by that sum.
  out.error = std::min(global, sum);
  out.where =
      global <= sum
          ? fmt::format("the replayed states at t = {:.6g}", out.replay_at)
          : fmt::format("the intervals' local errors summed; the replay from t0 deviates by {:.3g} at t = {:.6g}{}",
                        global, out.replay_at, out.replay_failure.empty() ? "" : " (" + out.replay_failure + ")");
  return out;
}

}  // namespace

PathError path_error(HermiteSimpson& problem, const std::vector<double>& z) {
  return problem.point_problem().dynamics ? replay_error(problem, z) : residual_error(problem, z);
}

}  // namespace nhc::optimize

namespace nhc::optimize {

std::vector<double> point_at(const HermiteSimpson& problem, const double* z, double fraction) {
  const std::vector<double> mesh = problem.mesh();
  const auto it = std::upper_bound(mesh.begin(), mesh.end(), fraction);
  const int k = std::clamp(static_cast<int>(it - mesh.begin()) - 1, 0, problem.intervals() - 1);
  const double a = mesh[static_cast<std::size_t>(k)], b = mesh[static_cast<std::size_t>(k) + 1];
  std::vector<double> point;
  interpolate(problem, z, k, std::clamp((fraction - a) / (b - a), 0.0, 1.0), point);
  return point;
}

std::vector<double> transfer(const HermiteSimpson& from, const std::vector<double>& z, const HermiteSimpson& to) {
  std::vector<double> out(static_cast<std::size_t>(to.variables()), 0.0);
  const int stride = to.point_problem().slots();
  if (to.variables() > to.points() * stride) out.back() = z.back();  // a free final time
  for (int j = 0; j < to.points(); ++j) {
    const std::vector<double> point = point_at(from, z.data(), to.fraction(j));
    std::copy(point.begin(), point.end(), out.begin() + static_cast<std::ptrdiff_t>(j) * stride);
  }
  for (std::size_t k = 0; k < out.size(); ++k)
    out[k] = std::clamp(out[k], to.variable_low(static_cast<int>(k)), to.variable_high(static_cast<int>(k)));
  return out;
}

}  // namespace nhc::optimize
