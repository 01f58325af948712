#include "nhc/runtime/sensitivity.hpp"

#include "nhc/base/number_text.hpp"

#include <idas/idas.h>
#include <idas/idas_ls.h>
#include <sunnonlinsol/sunnonlinsol_newton.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <sstream>
#include <memory>
#include <optional>
#include <type_traits>
#include <stdexcept>

#include "nhc/base/primed_name.hpp"
#include "nhc/runtime/hidden_constraints.hpp"
#include "nhc/runtime/ida_session.hpp"
#include "nhc/runtime/inputs.hpp"
#include "nhc/runtime/sundials.hpp"
#include "nhc/runtime/trajectory.hpp"

namespace nhc::runtime {

namespace sd = sun;

namespace {

/// An array of Ns serial vectors owned together (IDAS takes N_Vector*).
class VectorArray {
 public:
  VectorArray() = default;
  VectorArray(int count, N_Vector like) : count_(count), v_(count > 0 ? N_VCloneVectorArray(count, like) : nullptr) {
    for (int k = 0; k < count_; ++k) N_VConst(0.0, v_[k]);
  }
  ~VectorArray() {
    if (v_) N_VDestroyVectorArray(v_, count_);
  }
  VectorArray(VectorArray&& o) noexcept : count_(o.count_), v_(std::exchange(o.v_, nullptr)) {}
  VectorArray& operator=(VectorArray&& o) noexcept {
    if (this != &o) {
      if (v_) N_VDestroyVectorArray(v_, count_);
      count_ = o.count_;
      v_ = std::exchange(o.v_, nullptr);
    }
    return *this;
  }
  N_Vector* get() const noexcept { return v_; }
  double* data(int k) const noexcept { return N_VGetArrayPointer(v_[k]); }

 private:
  int count_ = 0;
  N_Vector* v_ = nullptr;
};

/// The staggered corrector's Newton solver, owned here so that its convergence test is ours.
struct NonlinearSolverFree {
  void operator()(SUNNonlinearSolver solver) const noexcept { SUNNonlinSolFree(solver); }
};
using NonlinearSolver = std::unique_ptr<std::remove_pointer_t<SUNNonlinearSolver>, NonlinearSolverFree>;

}  // namespace

SensitivityParameter sensitivity_parameter(const Model& model, const std::string& name) {
  SensitivityParameter theta;
  theta.name = name;
  const std::string suffix = "(0)";
  if (name.size() > suffix.size() && name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
    const std::string state = name.substr(0, name.size() - suffix.size());
    for (int i = 0; i < model.n_states(); ++i)
      if (model.state_name(i) == state) {
        if (!model.is_differential(i))
          throw std::invalid_argument(name + " is the initial value of an algebraic state of the " +
                                      model.model_name() + " model: it follows from the others and cannot be varied");
        theta.kind = SensitivityParameter::Kind::initial_value;
        theta.index = i;
        return theta;
      }
    std::string states;
    for (int i = 0; i < model.n_states(); ++i)
      if (model.is_differential(i)) states += (states.empty() ? "" : ", ") + model.state_name(i) + "(0)";
    throw std::invalid_argument("unknown initial value " + name + " (the " + model.model_name() + " model has " +
                                states + ")");
  }
  const int k = model.parameter_index(name);
  if (k < 0) {
    std::string names;
    for (int j = 0; j < model.n_parameters(); ++j)
      names += (j ? ", " : "") + std::string(model.table().parameter_names[j]);
    throw std::invalid_argument("unknown parameter " + name + " (parameters: " + (names.empty() ? "none" : names) +
                                "; an initial value is written x(0) or x'(0))");
  }
  theta.kind = SensitivityParameter::Kind::parameter;
  theta.index = k;
  return theta;
}

std::vector<SensitivityParameter> sensitivity_parameters(const Model& model, const std::vector<std::string>& names) {
  std::vector<SensitivityParameter> thetas;
  for (const std::string& name : names) {
    thetas.push_back(sensitivity_parameter(model, name));
    for (size_t k = 0; k + 1 < thetas.size(); ++k)
      if (thetas[k].kind == thetas.back().kind && thetas[k].index == thetas.back().index)
        throw std::invalid_argument(name + " is named twice");
  }
  return thetas;
}

void require_given(const std::vector<SensitivityParameter>& thetas, const InitialState& initial) {
  for (const SensitivityParameter& th : thetas) {
    if (th.kind != SensitivityParameter::Kind::initial_value) continue;
    const auto i = static_cast<std::size_t>(th.index);
    if (i >= initial.given.size() || !initial.given[i])
      throw std::invalid_argument(th.name +
                                  " is not given in the scene: it follows from the hidden constraints and the given "
                                  "values, so it cannot be varied on its own");
  }
}

struct SensitivityIntegrator::Impl {
  Model model;
  std::vector<double> p;
  std::vector<SensitivityParameter> thetas;
  IntegratorOptions options;
  SensitivityOptions sensitivity;
  /// The parameters, then the inputs at their default signals at each evaluation (inputs.hpp):
  /// what the generated functions read. dF/dp includes the signals' dependence on the parameters
  /// (emit/parameter_jacobian.hpp).
  std::optional<InputValues> inputs;
  const double* pu(double tt, const double* yy) const { return inputs->at(tt, yy); }

  sd::Context ctx;
  sd::Vector y, yp, id;
  VectorArray yS, ypS;
  sd::Matrix A;
  sd::LinearSolver solver;
  NonlinearSolver sensitivity_newton;  // before ida: IDAFree runs first and leaves it alone
  double first_correction = 0;         // the sensitivity corrector's first correction (weighted norm)
  sd::IdaMemory ida;
  bool sparse = false;
  std::string jacobian_kind;
  std::string last_message;
  /// IDASolve runs to the next output in one call, which with the sensitivities may take minutes:
  /// the stop request is also asked every kStopCheckEvaluations residual evaluations, and a yes
  /// fails the residual (unrecoverably) so that IDAS returns and the run stops.
  static constexpr long kStopCheckEvaluations = 32;
  long residual_calls = 0;
  bool stop_seen = false;
  double t = 0;
  bool initialized = false;
  double init_seconds = 0, integrate_seconds = 0;
  std::vector<double> singular_scale;
  std::vector<double> singular_values;  // every monitor at the root function's point
  std::vector<int> root_monitors;       // the monitors IDA watches: all but the Euler angles'

  // The sensitivity residual's matrices dF/dy, dF/dy' at the last (t, y, y') (the staggered
  // corrector calls it repeatedly at the same point) and dF/dp.
  double cached_t = NAN;
  std::vector<double> cached_y, cached_yp;
  Eigen::MatrixXd Fy, Fyp, Fp;                // dense models
  std::vector<double> Fy_values, Fyp_values;  // sparse models, compressed-column values

  /// r = F_y s + F_y' s' with the matrices of update_matrices().
  void apply(const double* s, const double* sp, double* r) const {
    const int nn = n();
    if (!model.has_sparse_jacobian()) {
      Eigen::Map<Eigen::VectorXd> out(r, nn);
      out.noalias() = Fy * Eigen::Map<const Eigen::VectorXd>(s, nn);
      out.noalias() += Fyp * Eigen::Map<const Eigen::VectorXd>(sp, nn);
      return;
    }
    const auto& tab = model.table();
    std::fill(r, r + nn, 0.0);
    for (int j = 0; j < nn; ++j)
      for (int k = tab.jacobian_colptr[j]; k < tab.jacobian_colptr[j + 1]; ++k)
        r[tab.jacobian_rowind[k]] +=
            Fy_values[static_cast<size_t>(k)] * s[j] + Fyp_values[static_cast<size_t>(k)] * sp[j];
  }

  Impl(Model m, std::vector<double> params, std::vector<SensitivityParameter> th, IntegratorOptions o,
       SensitivityOptions so)
      : model(std::move(m)), p(std::move(params)), thetas(std::move(th)), options(o), sensitivity(so) {
    if (p.empty()) p = model.default_parameters();
    if (static_cast<int>(p.size()) != model.n_parameters())
      throw base::ModelError("the model has " + std::to_string(model.n_parameters()) + " parameters, " +
                             std::to_string(p.size()) + " given");
    // The inputs follow their default signals s(t, p), of which the generated dF/dp is the total
    // derivative (∂F/∂p + ∂F/∂u ∂s/∂p); inputs set otherwise would need their own ∂u/∂p.
    inputs.emplace(model, p);
    if (thetas.empty()) throw std::invalid_argument("no quantity to differentiate by");
    if (!model.has_dense_jacobian() && !model.has_sparse_jacobian())
      throw base::ModelError("sensitivities need the generated Jacobian (generate with --jacobian dense or sparse)");
    for (const SensitivityParameter& th : thetas)
      if (th.kind == SensitivityParameter::Kind::parameter && !model.has_parameter_jacobian())
        throw base::ModelError(
            "sensitivities with respect to parameters need dF/dp: generate the model with --sensitivities");
  }

  int n() const { return model.n_states(); }
  int ns() const { return static_cast<int>(thetas.size()); }

  void update_matrices(double tt, const double* yy, const double* ypp) {
    const int nn = n();
    if (tt == cached_t && std::equal(yy, yy + nn, cached_y.begin()) && std::equal(ypp, ypp + nn, cached_yp.begin()))
      return;
    const auto& tab = model.table();
    if (model.has_sparse_jacobian()) {  // the compressed columns: linear in the nonzeros
      Fy_values.resize(static_cast<size_t>(tab.jacobian_nnz));
      Fyp_values.resize(static_cast<size_t>(tab.jacobian_nnz));
      tab.jacobian_values(tt, yy, ypp, 0.0, pu(tt, yy), Fy_values.data());   // dF/dy
      tab.jacobian_values(tt, yy, ypp, 1.0, pu(tt, yy), Fyp_values.data());  // dF/dy + dF/dy'
      for (size_t k = 0; k < Fyp_values.size(); ++k) Fyp_values[k] -= Fy_values[k];
    } else {
      Fy.resize(nn, nn);
      Fyp.resize(nn, nn);
      model.dense_jacobian(tt, yy, ypp, 0.0, pu(tt, yy), Fy.data());   // dF/dy
      model.dense_jacobian(tt, yy, ypp, 1.0, pu(tt, yy), Fyp.data());  // dF/dy + dF/dy'
      Fyp -= Fy;
    }
    if (model.n_parameters() > 0 && model.has_parameter_jacobian()) {
      Fp.resize(nn, model.n_parameters());
      model.table().residual_parameter_jacobian(tt, yy, ypp, pu(tt, yy), Fp.data());
    }
    cached_t = tt;
    cached_y.assign(yy, yy + nn);
    cached_yp.assign(ypp, ypp + nn);
  }

  // ---- callbacks -------------------------------------------------------------------------

  static int residual_cb(sunrealtype tt, N_Vector yy, N_Vector ypp, N_Vector rr, void* data) {
    auto* self = static_cast<Impl*>(data);
    if (self->options.stop_requested && ++self->residual_calls % kStopCheckEvaluations == 0 &&
        self->options.stop_requested()) {
      self->stop_seen = true;
      return -1;
    }
    double* r = N_VGetArrayPointer(rr);
    self->model.table().residual(tt, N_VGetArrayPointer(yy), N_VGetArrayPointer(ypp),
                                 self->pu(tt, N_VGetArrayPointer(yy)), r);
    for (int i = 0; i < self->n(); ++i)
      if (!std::isfinite(r[i])) return 1;
    return 0;
  }

  /// F_y s_k + F_y' s_k' + ∂F/∂θ_k for every k (IDASensResFn).
  static int sensitivity_residual_cb(int count, sunrealtype tt, N_Vector yy, N_Vector ypp, N_Vector, N_Vector* yyS,
                                     N_Vector* ypS, N_Vector* rrS, void* data, N_Vector, N_Vector, N_Vector) {
    auto* self = static_cast<Impl*>(data);
    const int nn = self->n();
    self->update_matrices(tt, N_VGetArrayPointer(yy), N_VGetArrayPointer(ypp));
    for (int k = 0; k < count; ++k) {
      self->apply(N_VGetArrayPointer(yyS[k]), N_VGetArrayPointer(ypS[k]), N_VGetArrayPointer(rrS[k]));
      Eigen::Map<Eigen::VectorXd> r(N_VGetArrayPointer(rrS[k]), nn);
      const SensitivityParameter& th = self->thetas[static_cast<size_t>(k)];
      if (th.kind == SensitivityParameter::Kind::parameter) r += self->Fp.col(th.index);
      if (!r.allFinite()) return 1;
    }
    return 0;
  }

  /// Convergence test of the staggered sensitivity corrector (SUNNonlinSolConvTestFn). IDAS's own
  /// (idas_nls_stg.c, SUNDIALS 6.4) accepts the first correction when its rate estimate ssS, kept
  /// from an earlier step, times the correction is below tol: the sensitivity DAE is linear, so a
  /// fresh iteration matrix makes that rate ~0, and afterwards every first correction passes
  /// however stale the matrix (in y: IDAS resets ssS only when cj changes). With the error test
  /// off nothing else catches the error, and on the knife edge on an incline the sensitivities
  /// grew to 1e9 by t = 2. Here the rate is measured in every solve, from the second
  /// correction, as IDAS measures it for the state (idas_nls.c, idaNlsConvTest): accept when
  /// rate/(1-rate)·|δ_m| <= tol, or at once when |δ_0| <= 1e-4 tol.
  static int sensitivity_convergence_cb(SUNNonlinearSolver solver, N_Vector, N_Vector del, sunrealtype tol,
                                        N_Vector ewt, void* data) {
    auto* self = static_cast<Impl*>(data);
    const double norm = N_VWrmsNorm(del, ewt);
    int m = 0;
    if (SUNNonlinSolGetCurIter(solver, &m) != SUN_NLS_SUCCESS) return -1;
    if (m == 0) {
      self->first_correction = norm;
      return norm <= 1e-4 * tol ? SUN_NLS_SUCCESS : SUN_NLS_CONTINUE;
    }
    const double rate = std::pow(norm / self->first_correction, 1.0 / m);
    if (rate > 0.9) return SUN_NLS_CONV_RECVR;  // IDAS's RATEMAX
    return rate / (1.0 - rate) * norm <= tol ? SUN_NLS_SUCCESS : SUN_NLS_CONTINUE;
  }

  static int jacobian_cb(sunrealtype tt, sunrealtype cj, N_Vector yy, N_Vector ypp, N_Vector, SUNMatrix J, void* data,
                         N_Vector, N_Vector, N_Vector) {
    auto* self = static_cast<Impl*>(data);
    return ida_session::fill_jacobian(self->model, self->sparse, tt, N_VGetArrayPointer(yy), N_VGetArrayPointer(ypp),
                                      cj, self->pu(tt, N_VGetArrayPointer(yy)), J) < 0
               ? 0
               : 1;
  }

  static int root_cb(sunrealtype tt, N_Vector yy, N_Vector, sunrealtype* gout, void* data) {
    auto* self = static_cast<Impl*>(data);
    std::vector<double>& s = self->singular_values;
    self->model.table().singular_quantities(tt, N_VGetArrayPointer(yy), self->pu(tt, N_VGetArrayPointer(yy)), s.data());
    for (std::size_t r = 0; r < self->root_monitors.size(); ++r) {
      const auto k = static_cast<std::size_t>(self->root_monitors[r]);
      gout[r] = std::abs(s[k]) - self->options.singularity_threshold * self->singular_scale[k];
      if (!std::isfinite(gout[r])) gout[r] = -1.0;
    }
    return 0;
  }

  static void error_handler_cb(int, const char*, const char*, char* message, void* data) {
    static_cast<Impl*>(data)->last_message = message ? message : "";
  }

  // ---- set-up ----------------------------------------------------------------------------

  void check(int flag, const char* what) {
    if (flag >= 0) return;
    double tcur = t;
    if (ida) IDAGetCurrentTime(ida, &tcur);
    sd::check(flag, what, tcur, last_message);
  }

  [[noreturn]] void fail(int flag, const char* what) {
    double tcur = t;
    IDAGetCurrentTime(ida, &tcur);
    if (stop_seen)
      throw base::SolverError(base::FailureKind::stopped, tcur,
                              "the run was stopped at t = " + base::number_text(tcur, 15));
    const std::string cause = std::string(what) + " failed at t = " + base::number_text(tcur, 15) + ": " +
                              sd::describe_ida_flag(flag) + (last_message.empty() ? "" : " (" + last_message + ")");
    if (auto error = ida_session::euler_angles_failure(model, t, y.data(), pu(t, y.data()), cause)) throw *error;
    throw base::SolverError(sd::classify_ida_flag(flag), tcur, cause);
  }

  void create_linear_solver() {
    ida_session::LinearSystem ls =
        ida_session::attach_linear_solver(ida, model, options.linear_solver, y, ctx, &Impl::jacobian_cb,
                                          [this](int flag, const char* what) { check(flag, what); });
    A = std::move(ls.A);
    solver = std::move(ls.solver);
    sparse = ls.sparse;
    jacobian_kind = ls.jacobian_kind;
  }

  /// Without the sensitivities in the error test, their accuracy rests on the corrector alone:
  /// replace IDAS's convergence test by sensitivity_convergence_cb. (With the error test on,
  /// IDAS's cheaper test stays: a poorly converged s fails the error test and the step is retried.)
  void use_strict_sensitivity_corrector() {
    sensitivity_newton = NonlinearSolver(SUNNonlinSol_NewtonSens(ns(), y, ctx));
    if (!sensitivity_newton)
      throw base::SolverError(base::FailureKind::setup, t, "creating the sensitivity corrector failed");
    check(IDASetNonlinearSolverSensStg(ida, sensitivity_newton.get()), "attaching the sensitivity corrector");
    check(SUNNonlinSolSetConvTestFn(sensitivity_newton.get(), &Impl::sensitivity_convergence_cb, this),
          "setting the sensitivity corrector's convergence test");
  }

  /// The differential-state components of s(t0): e_i for an initial value, the minimum-norm
  /// solution of the differentiated hidden constraints for the states that are not given.
  void initial_sensitivities(const InitialState& state) {
    const int nn = n(), m = model.n_hidden();
    std::vector<bool> fixed(static_cast<size_t>(nn), false);
    for (int i = 0; i < nn && i < static_cast<int>(state.given.size()); ++i)
      fixed[static_cast<size_t>(i)] = state.given[static_cast<size_t>(i)];
    Eigen::MatrixXd G, Gp;
    if (m > 0) {
      G.resize(m, nn);
      model.table().hidden_constraints_jacobian(state.t0, y.data(), pu(state.t0, y.data()), G.data());
      if (model.n_parameters() > 0 && model.table().abi_version >= 3 && model.table().hidden_parameter_jacobian) {
        Gp.resize(m, model.n_parameters());
        model.table().hidden_parameter_jacobian(state.t0, y.data(), pu(state.t0, y.data()), Gp.data());
      }
    }
    std::vector<int> free;
    for (int i = 0; i < nn; ++i)
      if (!fixed[static_cast<size_t>(i)]) free.push_back(i);
    for (int k = 0; k < ns(); ++k) {
      const SensitivityParameter& th = thetas[static_cast<size_t>(k)];
      Eigen::Map<Eigen::VectorXd> s(yS.data(k), nn);
      s.setZero();
      Eigen::Map<Eigen::VectorXd>(ypS.data(k), nn).setZero();
      if (th.kind == SensitivityParameter::Kind::initial_value) {
        if (!fixed[static_cast<size_t>(th.index)])
          throw base::SolverError(base::FailureKind::inconsistent_initial_values, state.t0,
                                  th.name +
                                      " is not given: it follows from the hidden constraints and the given values, "
                                      "so it cannot be varied on its own");
        s[th.index] = 1.0;
      }
      // Given values written through θ (x(0) = A): they move with it, and stay given.
      for (int i = 0; i < nn && i < static_cast<int>(th.initial_slope.size()); ++i)
        if (fixed[static_cast<size_t>(i)]) s[i] += th.initial_slope[static_cast<size_t>(i)];
      if (m == 0 || free.empty()) continue;
      Eigen::VectorXd rhs = G * s;  // G_fixed s_fixed (s_free is still 0)
      if (th.kind == SensitivityParameter::Kind::parameter && Gp.size() > 0) rhs += Gp.col(th.index);
      Eigen::MatrixXd Gfree(m, static_cast<int>(free.size()));
      for (size_t j = 0; j < free.size(); ++j) Gfree.col(static_cast<int>(j)) = G.col(free[j]);
      Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(Gfree);
      cod.setThreshold(1e-12);
      const Eigen::VectorXd ds = cod.solve(-rhs);
      for (size_t j = 0; j < free.size(); ++j) s[free[j]] = ds[static_cast<int>(j)];
    }
  }

  Statistics counters() const {
    Statistics st = ida_session::counters(ida, !root_monitors.empty());
    st.initialization_seconds = init_seconds;
    st.integration_seconds = integrate_seconds;
    st.linear_solver = sparse ? "KLU" : "dense";
    st.jacobian = jacobian_kind;
    return st;
  }

  SensitivitySample current(double tt) const {
    SensitivitySample out;
    out.t = tt;
    out.y.assign(y.data(), y.data() + n());
    out.yp.assign(yp.data(), yp.data() + n());
    const double* values = pu(tt, out.y.data()) + model.n_parameters();
    out.u.assign(values, values + model.n_inputs());
    for (int k = 0; k < ns(); ++k) {
      out.s.emplace_back(yS.data(k), yS.data(k) + n());
      out.sp.emplace_back(ypS.data(k), ypS.data(k) + n());
    }
    return out;
  }
};

SensitivityIntegrator::SensitivityIntegrator(Model model, std::vector<double> parameters,
                                             std::vector<SensitivityParameter> thetas, IntegratorOptions options,
                                             SensitivityOptions sensitivity)
    : impl_(std::make_unique<Impl>(std::move(model), std::move(parameters), std::move(thetas), options, sensitivity)) {}
SensitivityIntegrator::~SensitivityIntegrator() = default;
SensitivityIntegrator::SensitivityIntegrator(SensitivityIntegrator&&) noexcept = default;
SensitivityIntegrator& SensitivityIntegrator::operator=(SensitivityIntegrator&&) noexcept = default;

SensitivitySample SensitivityIntegrator::initialize(const InitialState& state, double t_next) {
  Impl& s = *impl_;
  const auto start = std::chrono::steady_clock::now();
  const int n = s.n();
  if (static_cast<int>(state.y.size()) != n)
    throw base::ModelError("initial state has " + std::to_string(state.y.size()) + " values, the model " +
                           std::to_string(n) + " states");
  if (!(t_next > state.t0)) throw std::invalid_argument("initialize: t_next must be after t0");
  s.ctx = sd::Context::create();
  s.y = sd::Vector::create(n, s.ctx);
  s.yp = sd::Vector::create(n, s.ctx);
  s.id = sd::Vector::create(n, s.ctx);
  for (int i = 0; i < n; ++i) {
    s.y[i] = state.y[static_cast<size_t>(i)];
    s.yp[i] = state.yp.empty() ? 0.0 : state.yp[static_cast<size_t>(i)];
    s.id[i] = s.model.table().differential_id[i];
  }
  s.t = state.t0;

  // 1. Hidden constraints: move what the user did not give (the plain run's rule).
  const std::vector<double> repair_scale = initial_repair_scale(state);
  solve_starting_point(s.model, s.pu(state.t0, s.y.data()), state.t0, s.y.data(), state.given, s.options.rtol,
                       s.options.atol, state.repair ? &repair_scale : nullptr);
  // 2. Their derivative: the initial sensitivities of the differential states.
  s.yS = VectorArray(s.ns(), s.y);
  s.ypS = VectorArray(s.ns(), s.y);
  s.initial_sensitivities(state);

  // 3. IDAS with the sensitivity DAE (staggered corrector: the sensitivities reuse the state's
  // iteration matrix), then IDACalcIC for the algebraic components and y', s'.
  s.ida = sd::IdaMemory::create(s.ctx);
  s.check(IDASetErrHandlerFn(s.ida, &Impl::error_handler_cb, &s), "installing the error handler");
  s.check(IDAInit(s.ida, &Impl::residual_cb, state.t0, s.y, s.yp), "initialising IDAS");
  s.check(IDASetUserData(s.ida, &s), "setting the user data");
  ida_session::configure(s.ida, s.options, s.id, [&s](int flag, const char* what) { s.check(flag, what); });
  s.create_linear_solver();
  s.check(IDASensInit(s.ida, s.ns(), IDA_STAGGERED, &Impl::sensitivity_residual_cb, s.yS.get(), s.ypS.get()),
          "initialising the sensitivities");
  if (!s.sensitivity.error_control) s.use_strict_sensitivity_corrector();
  // Tolerances for s_k estimated from the state's, scaled by |θ_k| (IDASensEEtolerances).
  std::vector<double> pbar(static_cast<size_t>(s.ns()), 1.0);
  for (int k = 0; k < s.ns(); ++k) {
    const SensitivityParameter& th = s.thetas[static_cast<size_t>(k)];
    const double value = th.kind == SensitivityParameter::Kind::parameter ? s.p[static_cast<size_t>(th.index)]
                         : th.kind == SensitivityParameter::Kind::start   ? th.value
                                                                          : s.y[th.index];
    if (value != 0 && std::isfinite(value)) pbar[static_cast<size_t>(k)] = std::abs(value);
  }
  s.check(IDASetSensParams(s.ida, nullptr, pbar.data(), nullptr), "setting the sensitivity scales");
  s.check(IDASensEEtolerances(s.ida), "setting the sensitivity tolerances");
  s.check(IDASetSensErrCon(s.ida, s.sensitivity.error_control ? SUNTRUE : SUNFALSE),
          "setting the sensitivity error control");
  const int flag = IDACalcIC(s.ida, IDA_YA_YDP_INIT, t_next);
  if (flag < 0) s.fail(flag, "the consistent initialization with sensitivities (IDACalcIC)");
  s.check(IDAGetConsistentIC(s.ida, s.y, s.yp), "reading the consistent initial values");
  s.check(IDAGetSensConsistentIC(s.ida, s.yS.get(), s.ypS.get()), "reading the consistent initial sensitivities");

  s.root_monitors = ida_session::root_monitors(s.model);
  const int count = static_cast<int>(s.root_monitors.size());
  if (count > 0) {
    s.singular_values.assign(static_cast<size_t>(s.model.n_singular()), 0.0);
    s.singular_scale.assign(static_cast<size_t>(s.model.n_singular()), 0.0);
    s.model.table().singular_quantities(state.t0, s.y.data(), s.pu(state.t0, s.y.data()), s.singular_scale.data());
    for (double& v : s.singular_scale) v = std::abs(v);
    s.check(IDARootInit(s.ida, count, &Impl::root_cb), "initialising the singular-set monitors");
    std::vector<int> direction(static_cast<size_t>(count), -1);
    s.check(IDASetRootDirection(s.ida, direction.data()), "setting the monitor directions");
    s.check(IDASetNoInactiveRootWarn(s.ida), "configuring the monitors");
  }
  s.initialized = true;
  s.init_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return s.current(state.t0);
}

void SensitivityIntegrator::integrate(const std::vector<double>& times,
                                      const std::function<void(const SensitivitySample&)>& observer) {
  Impl& s = *impl_;
  if (!s.initialized) throw std::logic_error("integrate before initialize");
  if (times.empty()) return;
  const ida_session::Stopwatch stopwatch(s.integrate_seconds);
  s.check(IDASetStopTime(s.ida, times.back()), "setting the stop time");
  for (double tout : times) {
    if (tout <= s.t) {  // the current point (t0 at the start); earlier times are passed
      if (tout == s.t) observer(s.current(s.t));
      continue;
    }
    double tret = s.t;
    int flag = IDASolve(s.ida, tout, &tret, s.y, s.yp, IDA_NORMAL);
    if (flag < 0) s.fail(flag, "the integration with sensitivities");
    s.t = tret;
    s.check(IDAGetSens(s.ida, &tret, s.yS.get()), "reading the sensitivities");
    s.check(IDAGetSensDky(s.ida, tret, 1, s.ypS.get()), "reading the sensitivities' derivatives");
    observer(s.current(tret));
    if (s.options.stop_requested && s.options.stop_requested())
      throw base::SolverError(base::FailureKind::stopped, tret,
                              "the run was stopped at t = " + base::number_text(tret, 15));
    if (flag == IDA_ROOT_RETURN) {
      std::vector<int> found(s.root_monitors.size(), 0);
      s.check(IDAGetRootInfo(s.ida, found.data()), "reading the monitors");
      for (std::size_t r = 0; r < found.size(); ++r)
        if (found[r] != 0)
          throw base::SolverError(base::FailureKind::singular_constraint_gradient, tret,
                                  "the constraint gradient is singular at t = " + base::number_text(tret, 15) + ": " +
                                      s.model.singular_name(s.root_monitors[r]) +
                                      " reaches 0. The motion cannot be continued past this point.");
    }
  }
}

SensitivityStatistics SensitivityIntegrator::statistics() const {
  const Impl& s = *impl_;
  SensitivityStatistics st;
  if (!s.ida) return st;
  st.state = s.counters();
  IDAGetSensNumResEvals(s.ida, &st.sensitivity_residual_evaluations);
  IDAGetSensNumErrTestFails(s.ida, &st.sensitivity_error_test_failures);
  IDAGetSensNumNonlinSolvIters(s.ida, &st.sensitivity_nonlinear_iterations);
  return st;
}

const std::vector<SensitivityParameter>& SensitivityIntegrator::thetas() const { return impl_->thetas; }

SensitivityRun simulate_sensitivities(const Model& model, const std::vector<double>& p, const InitialState& initial,
                                      const std::vector<SensitivityParameter>& thetas, const std::vector<double>& times,
                                      const IntegratorOptions& options, const SensitivityOptions& sensitivity) {
  SensitivityRun run;
  SensitivityIntegrator integrator(model, p, thetas, options, sensitivity);
  try {
    const double t_next = first_output_after(times, initial.t0);
    integrator.initialize(initial, t_next);
    integrator.integrate(times, [&](const SensitivitySample& sample) { run.samples.push_back(sample); });
  } catch (const base::SolverError& e) {
    run.failure = e;
  }
  run.statistics = integrator.statistics();
  return run;
}

namespace {

/// For each CSV state column (csv_header order): the state index and whether it is read from y'.
std::vector<std::pair<int, bool>> state_columns(const Model& model) {
  std::vector<std::pair<int, bool>> columns;
  const int unknowns = model.n_coordinates() + model.n_multipliers();
  for (int v = 0; v < unknowns; ++v) {
    int top = -1;
    for (int i = 0; i < model.n_states(); ++i)
      if (model.table().state_variable[i] == v) {
        columns.emplace_back(i, false);
        if (model.is_differential(i) && (top < 0 || model.table().state_order[i] > model.table().state_order[top]))
          top = i;
      }
    if (top >= 0) columns.emplace_back(top, true);
  }
  return columns;
}

}  // namespace

std::vector<std::string> sensitivity_csv_header(const Model& model, const std::vector<SensitivityParameter>& thetas) {
  std::vector<std::string> header;
  for (const SensitivityParameter& th : thetas)
    for (const auto& [state, derivative] : state_columns(model))
      header.push_back("d(" + base::primed_name(model.state_name(state), derivative ? 1 : 0) + ")/d(" + th.name + ")");
  return header;
}

void sensitivity_values(const Model& model, const SensitivitySample& sample, std::vector<double>& values) {
  values.clear();
  const auto columns = state_columns(model);
  for (size_t k = 0; k < sample.s.size(); ++k)
    for (const auto& [state, derivative] : columns)
      values.push_back(derivative ? sample.sp[k][static_cast<size_t>(state)] : sample.s[k][static_cast<size_t>(state)]);
}

void write_sensitivity_csv(std::ostream& out, const Model& model, const std::vector<double>& p,
                           const std::vector<SensitivityParameter>& thetas,
                           const std::vector<SensitivitySample>& samples) {
  // The plain columns from write_csv, line by line, then ours appended to each line.
  std::vector<Sample> states;
  states.reserve(samples.size());
  for (const SensitivitySample& s : samples) states.push_back(s.state());
  std::ostringstream plain;
  write_csv(plain, model, p, states);
  std::istringstream lines(plain.str());
  std::string line;
  std::getline(lines, line);
  out << line;
  for (const std::string& name : sensitivity_csv_header(model, thetas)) out << ',' << name;
  out << '\n';
  std::vector<double> values;
  for (const SensitivitySample& s : samples) {
    std::getline(lines, line);
    sensitivity_values(model, s, values);
    for (double v : values) base::append_shortest(line, ',', v);
    line += '\n';
    out << line;
  }
}

}  // namespace nhc::runtime
