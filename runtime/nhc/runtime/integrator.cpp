#include "nhc/runtime/integrator.hpp"

#include "nhc/base/number_text.hpp"
#include "nhc/runtime/inputs.hpp"

#include <idas/idas.h>  // IDAS, a superset of IDA: one library for plain runs and sensitivities
#include <idas/idas_ls.h>
#include <sundials/sundials_config.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunlinsol/sunlinsol_klu.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunmatrix/sunmatrix_sparse.h>

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

#include "nhc/base/constraint_solver.hpp"
#include "nhc/runtime/hidden_constraints.hpp"
#include "nhc/runtime/ida_session.hpp"
#include "nhc/base/primed_name.hpp"
#include "nhc/runtime/sundials.hpp"

namespace nhc::runtime {

namespace sd = sun;

static_assert(SUNDIALS_VERSION_MAJOR == 6,
              "ProjectionMethod::in_place shifts IDA 6's divided difference phi[0] (sun::CloneRecorder)");

bool uses_sparse_solver(const Model& model, LinearSolverKind kind) {
  switch (kind) {
    case LinearSolverKind::sparse:
      if (!model.has_sparse_jacobian())
        throw base::ModelError(
            "KLU needs the sparse Jacobian, and this model was generated without it "
            "(generate the header with --jacobian sparse)");
      return true;
    case LinearSolverKind::dense:
      return false;
    case LinearSolverKind::automatic:
      return model.has_sparse_jacobian();
  }
  return false;
}

namespace {

/// The first non-finite value a callback met since the last accepted step.
struct NonFinite {
  bool seen = false;
  double t = 0;
  int index = 0;
  bool in_jacobian = false;
  long step = 0;          ///< accepted steps before it happened
  std::vector<double> y;  ///< the state at which it happened
};

/// Pseudo return flag: the step size collapsed (IDA crawls towards a point it cannot pass).
constexpr int kStepSizeCollapse = -1000;
/// Steps in a row with h < kTinyStep max(1, |t|) that count as a collapse.
constexpr int kCollapseSteps = 20;
constexpr double kTinyStep = 1e-12;

/// Sub-intervals of each step on which the events are sampled (docs/events.md), doubled while
/// the samples show more turns of an event than the coarser ones did, up to the largest count.
constexpr int kEventSubintervals = 8;
constexpr int kMaxEventSubintervals = 1024;

/// A located zero of an event in the last step: at t, the value's sign changed from `from`.
struct EventRoot {
  double t = 0;
  int event = 0;
  int direction = 0;  ///< +1 from below, -1 from above
};

}  // namespace

InitialState initial_state_from(const Model& model, double t0,
                                const std::map<std::string, std::vector<double>>& values) {
  InitialState s;
  s.t0 = t0;
  const int n = model.n_states();
  s.y.assign(static_cast<std::size_t>(n), 0.0);
  s.yp.assign(static_cast<std::size_t>(n), 0.0);
  s.given.assign(static_cast<std::size_t>(n), false);
  for (int i = 0; i < n; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const auto it = values.find(model.variable_name(model.table().state_variable[i]));
    if (it == values.end()) continue;
    const auto order = static_cast<std::size_t>(model.table().state_order[i]);
    if (it->second.size() > order) {
      s.y[k] = it->second[order];
      s.given[k] = model.is_differential(i);  // algebraic values are only guesses
    }
    if (it->second.size() > order + 1) s.yp[k] = it->second[order + 1];
  }
  return s;
}

/// The tout IDACalcIC is given. It uses tout only for the direction and the scale of its first step,
/// h = 1e-3 (tout − t0), and its Newton matrix is ∂F/∂y' + ∂F/∂y / h: a first output far away (a
/// harmonic oscillator with --t-end 1e7 --outputs 1: h = 1e4) leaves the algebraic states' columns
/// at 1e-4 of the others and Newton fails although the point is consistent. So the span is at most
/// one time unit (the scale of most scenes' runs), or 1e-6 |t0| where one unit is lost in rounding.
namespace {
double calc_ic_tout(double t0, double t_next) { return t0 + std::min(t_next - t0, std::max(1.0, 1e-6 * std::abs(t0))); }
}  // namespace

double first_output_after(const std::vector<double>& times, double t0) {
  for (double t : times)
    if (t > t0) return t;
  return t0 + 1.0;
}

std::vector<double> initial_repair_scale(const InitialState& state) {
  std::vector<double> scale(state.y.size(), state.repair ? 1.0 : 0.0);
  for (std::size_t i = 0; i < scale.size() && i < state.pinned.size(); ++i)
    if (state.pinned[i]) scale[i] = 0.0;
  return scale;
}

struct Integrator::Impl {
  Model model;
  InputValues inputs;  ///< the parameters, then the inputs at each evaluation (inputs.hpp)
  IntegratorOptions options;
  std::vector<Event> user_events;
  std::vector<EventHit> hits;
  bool start_events_checked = false;  // Event::met_below_at_start, once per run
  std::vector<double> event_last;     // each user event's value at t, the last accepted point
  bool event_values_stale = true;     // t moved without the events (start, restart)
  long event_evaluations = 0;
  std::optional<base::SolverError> event_error;  // the last error an event function threw
  bool restart_pending = false;                  // a terminal event stopped the run inside IDA's last step
  std::vector<double> interp_y, interp_yp;       // the state on the interpolating polynomial

  sd::Context ctx;
  sd::Vector y, yp, id, work;
  sd::Matrix A;
  sd::LinearSolver solver;
  sd::IdaMemory ida;
  N_Vector history = nullptr;  // IDA's phi[0] (sun::find_solution_history), owned by IDA
  bool sparse = false;
  std::string jacobian_kind;

  std::vector<double> singular_scale;  // |s_k(t0)|
  std::vector<double> singular_values_scratch;
  std::vector<int> root_monitors;  // IDA's root functions (ida_session::root_monitors)

  NonFinite nonfinite;
  std::string last_message;  // from IDA's error handler

  double t = 0;  // last accepted time
  std::vector<double> y_last, yp_last;
  bool initialized = false;
  long accepted_steps = 0;
  int tiny_steps = 0;  // consecutive steps below kTinyStep
  bool have_last_output = false;
  double last_output_t = 0;
  std::vector<double> last_output_y, last_output_yp;  ///< the sample passed at last_output_t

  long projections = 0;
  double init_seconds = 0, integrate_seconds = 0;
  Statistics before_restarts;  // IDAReInit zeroes IDA's counters; they are summed here

  /// IDA's counters since the last (re)initialization.
  Statistics counters() const { return ida ? ida_session::counters(ida, n_roots() > 0) : Statistics{}; }

  Statistics total() const {
    Statistics st = counters();
    const Statistics& b = before_restarts;
    st.steps += b.steps;
    st.residual_evaluations += b.residual_evaluations;
    st.jacobian_evaluations += b.jacobian_evaluations;
    st.linear_solver_setups += b.linear_solver_setups;
    st.error_test_failures += b.error_test_failures;
    st.nonlinear_iterations += b.nonlinear_iterations;
    st.nonlinear_failures += b.nonlinear_failures;
    st.root_evaluations += b.root_evaluations;
    return st;
  }
  /// total() with the user events' evaluations (counted here, not by IDA).
  Statistics total_with_events() const {
    Statistics st = total();
    st.root_evaluations += event_evaluations;
    return st;
  }

  Impl(Model m, std::vector<double> params, IntegratorOptions opts)
      : model(std::move(m)),
        inputs(model, params.empty() ? model.default_parameters() : std::move(params)),
        options(opts),
        root_monitors(ida_session::root_monitors(model)) {
    singular_values_scratch.assign(static_cast<std::size_t>(model.n_singular()), 0.0);
  }

  int n() const { return model.n_states(); }
  /// IDA's root functions: the singular-set monitors but the Euler angles' (the user events are
  /// found by scan_events).
  int n_roots() const { return static_cast<int>(root_monitors.size()); }

  // ---- callbacks -------------------------------------------------------------------------

  void note_nonfinite(double tt, int index, bool in_jacobian, const double* yy) {
    nonfinite.seen = true;
    nonfinite.step = accepted_steps;
    nonfinite.t = tt;
    nonfinite.index = index;
    nonfinite.in_jacobian = in_jacobian;
    nonfinite.y.assign(yy, yy + n());
  }

  static int residual_cb(sunrealtype tt, N_Vector yy, N_Vector ypp, N_Vector rr, void* data) {
    auto* self = static_cast<Impl*>(data);
    const double* yv = N_VGetArrayPointer(yy);
    double* r = N_VGetArrayPointer(rr);
    self->model.table().residual(tt, yv, N_VGetArrayPointer(ypp), self->inputs.at(tt, yv), r);
    for (int i = 0; i < self->n(); ++i)
      if (!std::isfinite(r[i])) {
        self->note_nonfinite(tt, i, false, yv);
        return 1;  // recoverable: IDA retries with a smaller step, and reports if it cannot
      }
    return 0;
  }

  static int jacobian_cb(sunrealtype tt, sunrealtype cj, N_Vector yy, N_Vector ypp, N_Vector, SUNMatrix J, void* data,
                         N_Vector, N_Vector, N_Vector) {
    auto* self = static_cast<Impl*>(data);
    const double* yv = N_VGetArrayPointer(yy);
    const long bad = ida_session::fill_jacobian(self->model, self->sparse, tt, yv, N_VGetArrayPointer(ypp), cj,
                                                self->inputs.at(tt, yv), J);
    if (bad < 0) return 0;
    self->note_nonfinite(tt, static_cast<int>(bad), true, yv);
    return 1;
  }

  static int root_cb(sunrealtype tt, N_Vector yy, N_Vector, sunrealtype* gout, void* data) {
    auto* self = static_cast<Impl*>(data);
    const double* yv = N_VGetArrayPointer(yy);
    double* s = self->singular_values_scratch.data();
    self->model.table().singular_quantities(tt, yv, self->inputs.at(tt, yv), s);
    for (int r = 0; r < self->n_roots(); ++r) {
      const int k = self->root_monitors[static_cast<std::size_t>(r)];
      gout[r] = std::abs(s[k]) - self->options.singularity_threshold * self->singular_scale[k];
      if (!std::isfinite(gout[r])) gout[r] = -1.0;  // a monitor that is no longer finite has crossed
    }
    return 0;
  }

  // ---- user events -----------------------------------------------------------------------

  /// Event k's value at (tt, yy, yp), whatever it is; an event function that throws a SolverError
  /// (a front end's own words for a value that is not finite) counts as NaN there, its error kept.
  double raw_event_value(int k, double tt, const double* yy, const double* ypp) {
    ++event_evaluations;
    try {
      return user_events[static_cast<std::size_t>(k)].function(tt, yy, ypp);
    } catch (const base::SolverError& error) {
      event_error = error;
      return NAN;
    }
  }

  /// Event k's value at (tt, yy, yp); a value that is not a finite number ends the run here.
  double event_value(int k, double tt, const double* yy, const double* ypp) {
    const double v = raw_event_value(k, tt, yy, ypp);
    if (std::isfinite(v)) return v;
    throw_nonfinite_event(k, tt, v);
  }

  /// The failure of event k, not finite at tt (the last evaluation, which was there): the event
  /// function's own error when it threw one, else this one.
  [[noreturn]] void throw_nonfinite_event(int k, double tt, double v) {
    if (event_error && event_error->t() == tt) throw *event_error;
    const Event& e = user_events[static_cast<std::size_t>(k)];
    std::ostringstream os;
    os << "event " << e.name << " is " << (std::isnan(v) ? "NaN" : "infinite")
       << " at t = " << base::number_text(tt, 15)
       << ": its crossings cannot be told there (an event must be a finite number along the motion)";
    throw base::SolverError(base::FailureKind::other, tt, os.str());
  }

  /// The state at tt on IDA's interpolating polynomial of the last step (interp_y, interp_yp).
  void interpolate(double tt, N_Vector dky) {
    check(IDAGetDky(ida, tt, 0, dky), "interpolating the state for the events");
    interp_y.assign(N_VGetArrayPointer(dky), N_VGetArrayPointer(dky) + n());
    check(IDAGetDky(ida, tt, 1, dky), "interpolating the state for the events");
    interp_yp.assign(N_VGetArrayPointer(dky), N_VGetArrayPointer(dky) + n());
  }

  /// The events' values at the last accepted point (after the start or a restart).
  void refresh_event_values() {
    event_last.resize(user_events.size());
    for (int k = 0; k < static_cast<int>(user_events.size()); ++k)
      event_last[static_cast<std::size_t>(k)] = event_value(k, t, y_last.data(), yp_last.data());
    event_values_stale = false;
  }

  /// The zeros of every user event in the step (a, b] just taken, in time order (docs/events.md):
  /// the values at kEventSubintervals equal sub-intervals of the step on IDA's polynomial (more,
  /// doubling, while the finer samples show more turns than the coarser), each sign change
  /// between neighbours located by the Illinois method, and each turn of the samples towards zero
  /// (an interior extremum, or one in the first or last sub-interval told by the slope at the
  /// step's end) searched by golden sections for a point beyond zero: two crossings closer than
  /// the samples are both found. event_last becomes the values at b.
  std::vector<EventRoot> scan_events(double a, double b, N_Vector dky) {
    std::vector<EventRoot> roots;
    const int ne = static_cast<int>(user_events.size());
    const double h = b - a;
    if (ne == 0 || !(h > 0)) return roots;
    // Roots are located to IDA's own root tolerance, 100 units of rounding of |t| + |h|.
    const double tolerance = 100 * std::numeric_limits<double>::epsilon() * (std::abs(b) + h);
    const auto raw = [&](int k, double tt) {
      if (tt == b) return raw_event_value(k, tt, y.data(), yp.data());
      interpolate(tt, dky);
      return raw_event_value(k, tt, interp_y.data(), interp_yp.data());
    };
    // A value that is not finite: the error names the first instant it is not, located by
    // bisection from the step's start (where it was).
    const auto value = [&](int k, double tt) {
      const double v = raw(k, tt);
      if (std::isfinite(v)) return v;
      double lo = a, hi = tt, bad = v;
      for (int it = 0; it < 200 && hi - lo > tolerance; ++it) {
        const double mid = lo + (hi - lo) / 2;
        const double vm = raw(k, mid);
        if (std::isfinite(vm)) {
          lo = mid;
        } else {
          hi = mid;
          bad = vm;
        }
      }
      throw_nonfinite_event(k, hi, bad);
    };
    const auto sign = [](double v) { return v > 0 ? 1 : v < 0 ? -1 : 0; };
    for (int k = 0; k < ne; ++k) {
      const Event& e = user_events[static_cast<std::size_t>(k)];
      std::vector<double> ts, gs;
      for (int j = 0; j <= kEventSubintervals; ++j) {
        const double tt = j == kEventSubintervals ? b : a + h * j / kEventSubintervals;
        ts.push_back(tt);
        gs.push_back(j == 0 ? event_last[static_cast<std::size_t>(k)] : value(k, tt));
      }
      const auto turns = [&] {
        int count = 0, last = 0;
        for (std::size_t j = 1; j < gs.size(); ++j) {
          const int d = sign(gs[j] - gs[j - 1]);
          if (d != 0 && last != 0 && d != last) ++count;
          if (d != 0) last = d;
        }
        return count;
      };
      // An event that turns more than once within the step may turn more often than the samples
      // show: halve the sub-intervals while that reveals more turns.
      for (int count = turns(); count >= 2 && static_cast<int>(ts.size()) - 1 < kMaxEventSubintervals;) {
        std::vector<double> t2{ts[0]}, g2{gs[0]};
        for (std::size_t j = 1; j < ts.size(); ++j) {
          const double mid = ts[j - 1] + (ts[j] - ts[j - 1]) / 2;
          t2.push_back(mid);
          g2.push_back(value(k, mid));
          t2.push_back(ts[j]);
          g2.push_back(gs[j]);
        }
        ts.swap(t2);
        gs.swap(g2);
        const int finer = turns();
        if (finer <= count) break;
        count = finer;
      }
      const std::size_t last = ts.size() - 1;
      // Each bracket (l, r] holds a sign change: locate it (Illinois, on the polynomial).
      const auto locate = [&](double l, double gl, double r, double gr) {
        const int from = sign(gl);
        if (from == 0 || sign(gr) == from) return;
        const int direction = from < 0 ? 1 : -1;
        if (e.direction != 0 && e.direction != direction) return;
        int side = 0;
        for (int it = 0; it < 200 && gr != 0 && r - l > tolerance; ++it) {
          double m = r - gr * (r - l) / (gr - gl);
          if (!(m > l && m < r)) m = l + (r - l) / 2;
          const double gm = value(k, m);
          if (sign(gm) == from) {
            l = m, gl = gm;
            if (side == -1) gr /= 2;
            side = -1;
          } else {
            r = m, gr = gm;
            if (side == 1) gl /= 2;
            side = 1;
          }
        }
        roots.push_back({r, k, direction});
      };
      // A turn towards zero inside [l, r]: the extremum of sigma*g by golden sections, and, where
      // it lies beyond zero, the two crossings around it.
      const auto search_turn = [&](double l, double gl, double r, double gr) {
        const int sigma = sign(gl);
        if (sigma == 0 || sign(gr) != sigma) return;
        const double ratio = (std::sqrt(5.0) - 1) / 2;
        double lo = l, hi = r;
        double x1 = hi - ratio * (hi - lo), x2 = lo + ratio * (hi - lo);
        double f1 = value(k, x1), f2 = value(k, x2);
        for (int it = 0; it < 200 && hi - lo > tolerance; ++it) {
          if (sign(f1) != sigma || sign(f2) != sigma) break;
          if (sigma * f1 < sigma * f2) {
            hi = x2, x2 = x1, f2 = f1;
            x1 = hi - ratio * (hi - lo);
            f1 = value(k, x1);
          } else {
            lo = x1, x1 = x2, f1 = f2;
            x2 = lo + ratio * (hi - lo);
            f2 = value(k, x2);
          }
        }
        const bool first = sign(f1) != sigma, second = sign(f2) != sigma;
        if (!first && !second) return;
        const double x = first ? x1 : x2, fx = first ? f1 : f2;
        locate(l, gl, x, fx);
        locate(x, fx, r, gr);
      };
      for (std::size_t j = 1; j <= last; ++j) locate(ts[j - 1], gs[j - 1], ts[j], gs[j]);
      for (std::size_t j = 1; j < last; ++j) {
        const int s = sign(gs[j]);
        if (s != 0 && s * (gs[j] - gs[j - 1]) < 0 && s * (gs[j + 1] - gs[j]) > 0)
          search_turn(ts[j - 1], gs[j - 1], ts[j + 1], gs[j + 1]);
      }
      // Turns in the first and the last sub-interval: the slope at the step's ends says.
      const double delta = 1e-3 * (ts[1] - ts[0]);
      if (const int s = sign(gs[0]); s != 0 && s * (gs[1] - gs[0]) > 0 && delta > 0) {
        const double slope = value(k, ts[0] + delta) - gs[0];
        if (s * slope < 0) search_turn(ts[0], gs[0], ts[1], gs[1]);
      }
      if (const int s = sign(gs[last]); s != 0 && s * (gs[last] - gs[last - 1]) < 0 && delta > 0) {
        const double slope = gs[last] - value(k, ts[last] - delta);
        if (s * slope > 0) search_turn(ts[last - 1], gs[last - 1], ts[last], gs[last]);
      }
      event_last[static_cast<std::size_t>(k)] = gs[last];
    }
    std::sort(roots.begin(), roots.end(), [](const EventRoot& x, const EventRoot& y) { return x.t < y.t; });
    // Terminal events met at one instant (to 1e-9 of t's scale; their zeros are located apart to
    // the root tolerance): the first in the events' order is the one that ends the run, the
    // others are not reported (a contact's lift-off, listed before its slip, where F_n reaches
    // zero with no tangential force and mu F_n - |F_t| with it).
    const double same = 1e6 * std::numeric_limits<double>::epsilon() * (std::abs(b) + h);
    const auto terminal = [&](const EventRoot& r) { return user_events[static_cast<std::size_t>(r.event)].terminal; };
    const auto first = std::find_if(roots.begin(), roots.end(), terminal);
    if (first == roots.end()) return roots;
    const double t_first = first->t;
    const EventRoot* chosen = nullptr;
    for (const EventRoot& r : roots)
      if (terminal(r) && r.t <= t_first + same && (!chosen || r.event < chosen->event)) chosen = &r;
    std::vector<EventRoot> kept;
    for (const EventRoot& r : roots) {
      if (r.t > t_first + same) break;
      if (terminal(r) && &r != chosen) continue;
      if (&r == chosen) continue;
      kept.push_back(r);
    }
    EventRoot stop = *chosen;
    stop.t = t_first;  // the run ends at the first of the simultaneous zeros
    kept.push_back(stop);
    std::stable_sort(kept.begin(), kept.end(), [](const EventRoot& x, const EventRoot& y) { return x.t < y.t; });
    return kept;
  }

  static void error_handler_cb(int, const char*, const char*, char* message, void* data) {
    static_cast<Impl*>(data)->last_message = message ? message : "";
  }

  // ---- set-up ----------------------------------------------------------------------------

  void create_linear_solver() {
    ida_session::LinearSystem ls =
        ida_session::attach_linear_solver(ida, model, options.linear_solver, y, ctx, &Impl::jacobian_cb,
                                          [](int flag, const char* what) { sd::check(flag, what); });
    A = std::move(ls.A);
    solver = std::move(ls.solver);
    sparse = ls.sparse;
    jacobian_kind = ls.jacobian_kind;
  }

  void check(int flag, const char* what) {
    if (flag >= 0) return;
    double tcur = t;
    if (ida) IDAGetCurrentTime(ida, &tcur);
    sd::check(flag, what, tcur, last_message);
  }

  // ---- diagnostics -----------------------------------------------------------------------

  /// States with the largest components of a vector, by name: "x' (0.71), y' (0.71)".
  std::string dominant_states(const Eigen::VectorXd& v) const {
    std::vector<int> order(v.size());
    for (int i = 0; i < v.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](int a, int b) { return std::abs(v[a]) > std::abs(v[b]); });
    std::ostringstream os;
    const double top = std::abs(v[order[0]]);
    for (int k = 0; k < std::min<int>(3, v.size()); ++k) {
      if (k > 0 && std::abs(v[order[k]]) < 0.1 * top) break;
      os << (k ? ", " : "") << model.state_name(order[k]) << " (" << base::number_text(v[order[k]], 2) << ")";
    }
    return os.str();
  }

  /// What the index-1 system is solved for, in the scene's words: the leading derivatives (x'',
  /// z'', the derivative of each variable's highest differential state) and the algebraic states
  /// (lambda1), at most six named.
  std::string solved_quantities() const {
    std::vector<std::string> names;
    const auto& tab = model.table();
    for (int i = 0; i < n(); ++i)
      if (!model.is_differential(i)) names.push_back(model.state_name(i));
      else if (model.state_index(tab.state_variable[i], tab.state_order[i] + 1) < 0)
        names.push_back(base::primed_name(model.state_name(i), 1));
    std::string s;
    for (std::size_t k = 0; k < names.size() && k < 6; ++k) s += (k ? ", " : "") + names[k];
    if (names.size() > 6) s += ", …";
    return s;
  }

  /// The state of largest magnitude at the last accepted point when it is beyond 1e8 (the
  /// quantity that blew up), e.g. "; lambda1 blew up (lambda1 ≈ 4.7e+17 at the last accepted
  /// step)"; else "".
  std::string blown_up_state() const {
    int worst = -1;
    for (int i = 0; i < n() && i < static_cast<int>(y_last.size()); ++i)
      if (std::isfinite(y_last[i]) && std::abs(y_last[i]) > 1e8 &&
          (worst < 0 || std::abs(y_last[i]) > std::abs(y_last[worst])))
        worst = i;
    if (worst < 0) return "";
    return "; " + model.state_name(worst) + " blew up (" + model.state_name(worst) + " ≈ " +
           base::number_text(y_last[worst], 2) + " at the last accepted step)";
  }

  /// The singular-set monitor closest to zero relative to its start, if any is below `ratio`.
  int near_singular(double tt, const double* yy, double ratio) const {
    const int ns = model.n_singular();
    if (ns == 0) return -1;
    std::vector<double> s(ns);
    model.table().singular_quantities(tt, yy, inputs.at(tt, yy), s.data());
    int best = -1;
    double best_ratio = ratio;
    for (int k : root_monitors) {
      const double scale = k < static_cast<int>(singular_scale.size()) ? singular_scale[k] : 0.0;  // unset before t0
      const double r = scale > 0 ? std::abs(s[k]) / scale : std::abs(s[k]);
      if (!std::isfinite(s[k]) || r < best_ratio) best = k, best_ratio = std::isfinite(s[k]) ? r : 0;
    }
    return best;
  }

  /// The hidden-constraint gradient entry that is not finite at y, as "df1/dx'", or "".
  std::string nonfinite_constraint_gradient(double tt, const double* yy) const {
    const int m = model.n_hidden();
    if (m == 0) return "";
    std::vector<double> G(static_cast<size_t>(m) * n());
    model.table().hidden_constraints_jacobian(tt, yy, inputs.at(tt, yy), G.data());
    for (int j = 0; j < n(); ++j)
      for (int i = 0; i < m; ++i)
        if (!std::isfinite(G[i + static_cast<size_t>(m) * j]))
          return "d" + model.hidden_name(i) + "/d" + model.state_name(j);
    return "";
  }

  [[noreturn]] void throw_singular_gradient(double tt, int monitor, const std::string& entry) {
    std::ostringstream os;
    os << "the constraint gradient is singular at t = " << base::number_text(tt, 15) << ": ";
    if (monitor >= 0) os << model.singular_name(monitor) << " reaches 0";
    if (monitor >= 0 && !entry.empty()) os << "; ";
    if (!entry.empty()) os << entry << " is not defined there";
    os << ". The motion cannot be continued past this point.";
    throw base::SolverError(base::FailureKind::singular_constraint_gradient, tt, os.str());
  }

  /// Turns an IDA failure into the most specific SolverError we can justify.
  [[noreturn]] void fail(int flag, const char* what, double cj_override = 0) {
    double tcur = t;
    IDAGetCurrentTime(ida, &tcur);
    const double tt = std::max(tcur, t);
    const std::string symptom = flag == kStepSizeCollapse
                                    ? std::string("the step size collapsed below 1e-12 |t| for ") +
                                          std::to_string(kCollapseSteps) + " steps in a row"
                                    : sd::describe_ida_flag(flag);
    if (!y_last.empty())
      if (auto error = ida_session::euler_angles_failure(
              model, t, y_last.data(), inputs.at(t, y_last.data()),
              std::string(what) + " failed at t = " + base::number_text(tt, 15) + ": " + symptom))
        throw *error;

    if (nonfinite.seen && accepted_steps - nonfinite.step <= 2 * kCollapseSteps) {
      const std::string entry = nonfinite_constraint_gradient(nonfinite.t, nonfinite.y.data());
      const int monitor = near_singular(nonfinite.t, nonfinite.y.data(), 1e-3);
      if (!entry.empty() || monitor >= 0) throw_singular_gradient(nonfinite.t, monitor, entry);
      std::ostringstream os;
      if (nonfinite.in_jacobian) {
        const int row = nonfinite.index % n(), col = nonfinite.index / n();
        os << "the Jacobian of " << model.residual_name(sparse ? 0 : row);
        if (!sparse) os << " with respect to " << model.state_name(col);
        os << " is NaN or Inf";
      } else {
        os << "residual " << model.residual_name(nonfinite.index) << " is NaN or Inf";
      }
      os << " at t = " << base::number_text(nonfinite.t, 15) << " (" << what << ": " << symptom << ")";
      throw base::SolverError(base::FailureKind::nonfinite_residual, nonfinite.t, os.str());
    }

    // Near a singular set: name it rather than the symptom.
    const int monitor = near_singular(t, y_last.data(), 1e-4);
    if (monitor >= 0) throw_singular_gradient(t, monitor, "");

    // Is the iteration matrix singular at the last accepted point?
    long lsflag = 0;
    IDAGetLastLinFlag(ida, &lsflag);
    if (flag == IDA_LSETUP_FAIL || flag == IDA_LSOLVE_FAIL || flag == IDA_CONV_FAIL || flag == IDA_ERR_FAIL ||
        flag == IDA_NO_RECOVERY || flag == IDA_LINESEARCH_FAIL || flag == kStepSizeCollapse || lsflag > 0) {
      double cj = cj_override;
      if (cj <= 0) IDAGetCurrentCj(ida, &cj);
      Eigen::MatrixXd J = iteration_matrix(t, y_last.data(), yp_last.data(), cj);
      if (J.allFinite()) {
        Eigen::JacobiSVD<Eigen::MatrixXd> svd(J, Eigen::ComputeFullV);
        const auto& s = svd.singularValues();
        const double cond = s[0] > 0 ? s[0] / s[s.size() - 1] : INFINITY;
        if (lsflag > 0 || !(cond < (flag == kStepSizeCollapse ? 1e10 : 1e12))) {
          std::ostringstream os;
          // Not IDA's "dF/dy + cj dF/dy'": a scene may have a coordinate y. The null direction is
          // a correction of the states (and, times cj, of their derivatives) that the matrix loses.
          os << "the iteration matrix of the equations (dF/dstates + cj dF/dstates') is singular at t = "
             << base::number_text(tt, 15);
          os << " (condition number " << base::number_text(cond, 3)
             << "; the states it does not determine: " << dominant_states(svd.matrixV().col(s.size() - 1))
             << "): the equations cannot be solved there for " << solved_quantities() << blown_up_state();
          os << " (" << what << ": " << symptom << ")";
          throw base::SolverError(base::FailureKind::singular_iteration_matrix, tt, os.str());
        }
      }
    }
    if (flag == kStepSizeCollapse)
      throw base::SolverError(base::FailureKind::convergence, tt,
                              std::string(what) + " failed at t = " + base::number_text(tt, 15) + ": " + symptom +
                                  "; the solution cannot be continued past this point" + blown_up_state());
    try {
      sd::check(flag, what, tt, last_message);
    } catch (const base::SolverError& e) {
      const std::string blown = blown_up_state();
      if (blown.empty()) throw;
      throw base::SolverError(e.kind(), e.t(), e.what() + blown);
    }
    throw base::SolverError(base::FailureKind::other, tt,
                            std::string(what) + " failed at t = " + base::number_text(tt, 15));
  }

  /// dF/dy + cj dF/dy' from the generated Jacobian, or by differences of the residual.
  Eigen::MatrixXd iteration_matrix(double tt, const double* yy, const double* ypp, double cj) const {
    const int nn = n();
    const auto& tab = model.table();
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(nn, nn);
    if (!model.dense_jacobian(tt, yy, ypp, cj, inputs.at(tt, yy), J.data())) {
      std::vector<double> y1(yy, yy + nn), yp1(ypp, ypp + nn), r0(nn), r1(nn);
      tab.residual(tt, yy, ypp, inputs.at(tt, yy), r0.data());
      for (int j = 0; j < nn; ++j) {
        const double h = 1e-7 * std::max(1.0, std::abs(yy[j]));
        y1[j] += h;
        yp1[j] += cj * h;
        tab.residual(tt, y1.data(), yp1.data(), inputs.at(tt, y1.data()), r1.data());
        for (int i = 0; i < nn; ++i) J(i, j) = (r1[i] - r0[i]) / h;
        y1[j] = yy[j];
        yp1[j] = ypp[j];
      }
    }
    return J;
  }

  // ---- projection ------------------------------------------------------------------------

  /// Error-weight inverses atol + rtol |y_i| for the differential states, 0 for the algebraic ones.
  std::vector<double> projection_scale(const double* yy) const {
    std::vector<double> scale(n());
    for (int i = 0; i < n(); ++i)
      scale[i] = model.is_differential(i) ? options.atol + options.rtol * std::abs(yy[i]) : 0.0;
    return scale;
  }

  /// One Gauss–Newton correction's size in IDA's WRMS norm (0 when the constraints hold).
  double correction_norm(double tt, const double* yy, const std::vector<double>& scale) const {
    const int m = model.n_hidden(), nn = n();
    Eigen::VectorXd g(m);
    model.table().hidden_constraints(tt, yy, inputs.at(tt, yy), g.data());
    if (!g.allFinite()) return 0;
    Eigen::MatrixXd G(m, nn);
    model.table().hidden_constraints_jacobian(tt, yy, inputs.at(tt, yy), G.data());
    if (!G.allFinite()) return 0;
    Eigen::MatrixXd GD = G * Eigen::VectorXd::Map(scale.data(), nn).asDiagonal();
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(GD);
    Eigen::VectorXd u = cod.solve(g);  // correction / scale, componentwise
    return std::sqrt(u.squaredNorm() / nn);
  }

  // ---- the first step --------------------------------------------------------------------

  bool choose_first_step = true;   // a (re)start whose first step is still to be chosen
  bool first_step_pending = true;  // no step taken since the (re)start
  int first_step_retries = 0;

  /// The first step from the problem's own scale (IntegratorOptions::initial_step): 1e-3 of the
  /// way to the first output time t_first, and no longer than the step over which the rates y'
  /// move the differential states by half a tolerance unit in IDA's weighted norm (IDA's own
  /// rule, which it applies to the distance to its tout: the end of the run, here).
  void set_first_step(double t_first) {
    choose_first_step = false;
    first_step_pending = true;
    first_step_retries = 0;
    if (options.initial_step > 0) return;  // set by ida_session::configure
    double h = 1e-3 * (t_first - t);
    double sum = 0;
    for (int i = 0; i < n(); ++i) {
      if (!model.is_differential(i)) continue;
      const double w = yp_last[i] / (options.rtol * std::abs(y_last[i]) + options.atol);
      sum += w * w;
    }
    const double rate = std::sqrt(sum / n());
    if (rate > 0.5 / h) h = 0.5 / rate;
    if (h > 0 && std::isfinite(h)) check(IDASetInitStep(ida, h), "setting the first step");
  }

  /// A first step that IDA's error test or corrector refused as often as IDA allows (a start at
  /// rest whose motion begins with a high derivative at tight tolerances): start again from the
  /// same point with a step 1e-2 of the last one tried, at most four times. True when it did.
  bool retry_first_step(int flag, double t_final) {
    if (!first_step_pending || first_step_retries >= 4 || options.initial_step > 0) return false;
    if (flag != IDA_ERR_FAIL && flag != IDA_CONV_FAIL) return false;
    if (nonfinite.seen) return false;  // a NaN is not a matter of the step
    double h = 0;
    IDAGetCurrentStep(ida, &h);
    if (!(std::abs(h) > 0)) return false;
    ++first_step_retries;
    std::copy(y_last.begin(), y_last.end(), y.data());
    std::copy(yp_last.begin(), yp_last.end(), yp.data());
    before_restarts = total();
    check(IDAReInit(ida, t, y, yp), "restarting IDA with a shorter first step");
    check(IDASetInitStep(ida, 1e-2 * std::abs(h)), "setting the first step");
    check(IDASetStopTime(ida, t_final), "setting the stop time");
    return true;
  }

  /// Projects y at tt when the hidden constraints need it; true when it did.
  bool maybe_project(double tt) {
    if (options.projection == ProjectionMethod::none || model.n_hidden() == 0) return false;
    // The suslov model's hidden constraints are its monitored constraints f^α: the initial point
    // is put on them, but its equations do not keep them, so the motion is not projected.
    if (model.model_name() == "suslov") return false;
    double* yy = y.data();
    const std::vector<double> scale = projection_scale(yy);
    if (correction_norm(tt, yy, scale) <= options.projection_threshold) return false;
    if (options.projection == ProjectionMethod::in_place && history) {
      // phi[0] holds y_n; shifting it moves the predictor of the next step by the same Δy while
      // the higher differences (and so y' and the error estimate) stay: the step continues from
      // the projected point without a restart (the analogue of CVODE's projection, CVodeSetProjFn).
      std::vector<double> before(yy, yy + n());
      solve_hidden_constraints(model, inputs.at(tt, yy), tt, yy, scale, 1e-3 * options.atol);
      double* phi0 = N_VGetArrayPointer(history);
      for (int i = 0; i < n(); ++i) phi0[i] += yy[i] - before[i];
      ++projections;
      return true;
    }
    solve_hidden_constraints(model, inputs.at(tt, yy), tt, yy, scale, 1e-3 * options.atol);
    double h = 0;
    IDAGetLastStep(ida, &h);
    before_restarts = total();
    check(IDAReInit(ida, tt, y, yp), "restarting IDA after the projection");
    check(IDACalcIC(ida, IDA_YA_YDP_INIT, tt + std::max(h, 1e-10 * std::max(1.0, std::abs(tt)))),
          "recomputing y' and the algebraic states after the projection");
    check(IDAGetConsistentIC(ida, y, yp), "reading the projected point");
    ++projections;
    return true;
  }

  /// IDACalcIC for the algebraic states and y' at t0, asking of itself what the tolerances allow.
  /// Its Newton iteration stops when the weighted norm of the correction is below epsiccon
  /// (IDASetNonlinConvCoefIC, default 0.0033 of the error-test norm); with atol 1e-12 on states
  /// of size 1 to 100 (the Whipple bicycle) that is below what rounding in the residual lets its
  /// line search reach, and it fails although the point is consistent. On such a failure the
  /// calculation starts again from the same point with the test 10 and 100 times looser, then
  /// without the line search; the integrator's first steps correct what is left (their error
  /// test applies the tolerances in full).
  int consistent_initialization(double t0, double t_next) {
    t_next = calc_ic_tout(t0, t_next);
    const std::vector<double> y0(y.data(), y.data() + n()), yp0(yp.data(), yp.data() + n());
    int flag = IDACalcIC(ida, IDA_YA_YDP_INIT, t_next);
    double coefficient = 0.0033;
    for (int attempt = 0; attempt < 3 && (flag == IDA_LINESEARCH_FAIL || flag == IDA_CONSTR_FAIL ||
                                          flag == IDA_CONV_FAIL || flag == IDA_NO_RECOVERY);
         ++attempt) {
      if (nonfinite.seen) break;  // a NaN is not a matter of tolerance
      std::copy(y0.begin(), y0.end(), y.data());
      std::copy(yp0.begin(), yp0.end(), yp.data());
      check(IDAReInit(ida, t0, y, yp), "restarting the consistent initialization");
      if (attempt < 2) {
        coefficient *= 10;
        check(IDASetNonlinConvCoefIC(ida, coefficient), "loosening the initialization's convergence test");
      } else {
        check(IDASetLineSearchOffIC(ida, SUNTRUE), "turning off the initialization's line search");
      }
      flag = IDACalcIC(ida, IDA_YA_YDP_INIT, t_next);
    }
    return flag;
  }

  /// The sample last passed to the observer: where restart_at_last_output() starts again.
  void note_output(const Sample& sample) {
    have_last_output = true;
    last_output_t = sample.t;
    last_output_y = sample.y;
    last_output_yp = sample.yp;
  }

  /// Restarts IDA at the last output with the inputs as they are now: IDA's steps past that
  /// time used the old inputs, and a held input that jumps there makes y' jump (IDACalcIC
  /// recomputes it and the algebraic states, the states themselves stay).
  void restart_at_last_output() {
    if (!initialized) return;
    // Before any output: at the consistent initial point itself.
    const double t_out = have_last_output ? last_output_t : t;
    const std::vector<double>& y_out = have_last_output ? last_output_y : y_last;
    const std::vector<double>& yp_out = have_last_output ? last_output_yp : yp_last;
    std::copy(y_out.begin(), y_out.end(), y.data());
    std::copy(yp_out.begin(), yp_out.end(), yp.data());
    before_restarts = total();
    check(IDAReInit(ida, t_out, y, yp), "restarting IDA where the inputs change");
    check(IDACalcIC(ida, IDA_YA_YDP_INIT, t_out + 1e-6 * std::max(1.0, std::abs(t_out))),
          "recomputing y' and the algebraic states where the inputs change");
    check(IDAGetConsistentIC(ida, y, yp), "reading the point where the inputs change");
    remember(t_out, false);
    restart_pending = false;
    event_values_stale = true;  // y' and the multipliers follow the new inputs
    choose_first_step = true;
  }

  void remember(double tt, bool new_step = true) {
    t = tt;
    std::copy(y.data(), y.data() + n(), y_last.begin());
    std::copy(yp.data(), yp.data() + n(), yp_last.begin());
    if (new_step) ++accepted_steps;
  }
};

Integrator::Integrator(Model model, std::vector<double> parameters, IntegratorOptions options)
    : impl_(std::make_unique<Impl>(std::move(model), std::move(parameters), options)) {}
Integrator::~Integrator() = default;
Integrator::Integrator(Integrator&&) noexcept = default;
Integrator& Integrator::operator=(Integrator&&) noexcept = default;

void Integrator::set_inputs(InputFunction u) {
  impl_->inputs.set_function(std::move(u));
  impl_->restart_at_last_output();
}

void Integrator::hold_inputs(std::vector<double> u) {
  impl_->inputs.hold(std::move(u));
  impl_->restart_at_last_output();
}

Sample Integrator::point() const {
  const Impl& s = *impl_;
  if (!s.initialized) throw std::logic_error("point before initialize");
  Sample here{s.t, s.y_last, s.yp_last, {}};
  const double* p = s.inputs.at(s.t, here.y.data());
  here.u.assign(p + s.model.n_parameters(), p + s.model.n_parameters() + s.model.n_inputs());
  return here;
}

void Integrator::add_event(Event event) {
  if (impl_->initialized) throw std::logic_error("add_event after initialize");
  impl_->user_events.push_back(std::move(event));
}

Sample Integrator::initialize(const InitialState& state, double t_next) {
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
  s.y_last.assign(n, 0.0);
  s.yp_last.assign(n, 0.0);
  for (int i = 0; i < n; ++i) {
    s.y[i] = state.y[i];
    s.yp[i] = state.yp.empty() ? 0.0 : state.yp[i];
    s.id[i] = s.model.table().differential_id[i];
  }
  s.t = state.t0;

  // 1. Hidden constraints: move only what the user did not give (minimum-norm Gauss–Newton,
  //    constraint_solver.hpp; nhc analyze solves them with the same solver and tolerance).
  const std::vector<double> repair_scale = initial_repair_scale(state);
  solve_starting_point(s.model, s.inputs.at(state.t0, s.y.data()), state.t0, s.y.data(), state.given, s.options.rtol,
                       s.options.atol, state.repair ? &repair_scale : nullptr);

  // 2. IDA and IDACalcIC for the algebraic states and y'.
  s.ida = sd::IdaMemory::create(s.ctx);
  s.check(IDASetErrHandlerFn(s.ida, &Impl::error_handler_cb, &s), "installing the error handler");
  {
    sd::CloneRecorder recorder(s.y);
    s.check(IDAInit(s.ida, &Impl::residual_cb, state.t0, s.y, s.yp), "initialising IDA");
    s.history = sd::find_solution_history(recorder.clones(), s.y, s.yp);
  }
  s.check(IDASetUserData(s.ida, &s), "setting the user data");
  ida_session::configure(s.ida, s.options, s.id, [&s](int flag, const char* what) { s.check(flag, what); });
  s.create_linear_solver();

  auto nonfinite_at_start = [&](const char* stage) {
    if (!s.nonfinite.seen) return;
    const std::string entry = s.nonfinite_constraint_gradient(s.nonfinite.t, s.nonfinite.y.data());
    if (!entry.empty()) s.throw_singular_gradient(s.nonfinite.t, -1, entry);
    throw base::SolverError(base::FailureKind::nonfinite_residual, s.nonfinite.t,
                            std::string("residual ") + s.model.residual_name(s.nonfinite.index) +
                                " is NaN or Inf at t = " + base::number_text(s.nonfinite.t, 15) + " (" + stage + ")");
  };
  s.y_last.assign(s.y.data(), s.y.data() + n);  // the point a failure is diagnosed at
  s.yp_last.assign(s.yp.data(), s.yp.data() + n);
  const int flag = s.consistent_initialization(state.t0, t_next);
  if (flag < 0) {
    nonfinite_at_start("consistent initialization");
    // IDACalcIC's first step scale is 1e-3 of its span: its iteration matrix has cj ~ 1/that.
    s.fail(flag, "the consistent initialization of the algebraic states and the derivatives (IDACalcIC)",
           1e3 / (calc_ic_tout(state.t0, t_next) - state.t0));
  }
  s.check(IDAGetConsistentIC(s.ida, s.y, s.yp), "reading the consistent initial values");
  s.remember(state.t0);

  // 3. Singular-set monitors and events.
  const int ns = s.model.n_singular();
  if (ns > 0) {
    s.singular_scale.assign(ns, 0.0);
    s.model.table().singular_quantities(state.t0, s.y.data(), s.inputs.at(state.t0, s.y.data()),
                                        s.singular_scale.data());
    for (int k = 0; k < ns; ++k) s.singular_scale[k] = std::abs(s.singular_scale[k]);
    for (int k : s.root_monitors)
      if (!(s.singular_scale[k] > 0)) s.throw_singular_gradient(state.t0, k, "");
  }
  if (s.n_roots() > 0) {
    s.check(IDARootInit(s.ida, s.n_roots(), &Impl::root_cb), "initialising the event functions");
    std::vector<int> direction(s.n_roots(), -1);
    s.check(IDASetRootDirection(s.ida, direction.data()), "setting the monitors' directions");
    s.check(IDASetNoInactiveRootWarn(s.ida), "configuring the event functions");
  }
  s.initialized = true;
  s.init_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  Sample initial{state.t0, s.y_last, s.yp_last, {}};
  const double* p = s.inputs.at(state.t0, initial.y.data());
  initial.u.assign(p + s.model.n_parameters(), p + s.model.n_parameters() + s.model.n_inputs());
  return initial;
}

void Integrator::integrate(const std::vector<double>& times, const std::function<void(const Sample&)>& observer) {
  Impl& s = *impl_;
  if (!s.initialized) throw std::logic_error("integrate before initialize");
  if (times.empty()) return;
  const ida_session::Stopwatch stopwatch(s.integrate_seconds);

  const int n = s.n();
  const double t_final = times.back();
  ProgressReporter progress(s.options.progress, s.t, t_final);
  Sample out;
  out.y.resize(n);
  out.yp.resize(n);
  sd::Vector dky = sd::Vector::create(n, s.ctx);

  // Every sample goes out with the inputs at its point, and is remembered as the last output.
  auto deliver = [&](Sample& sample) {
    const double* p = s.inputs.at(sample.t, sample.y.data());
    sample.u.assign(p + s.model.n_parameters(), p + s.model.n_parameters() + s.model.n_inputs());
    observer(sample);
    s.note_output(sample);
  };
  auto emit_current = [&](double tt) {
    out.t = tt;
    out.y.assign(s.y.data(), s.y.data() + n);
    out.yp.assign(s.yp.data(), s.yp.data() + n);
    deliver(out);
  };
  auto emit_last_accepted = [&] {
    if (s.have_last_output && s.last_output_t >= s.t) return;
    out.t = s.t;
    out.y = s.y_last;
    out.yp = s.yp_last;
    deliver(out);
  };

  size_t next = 0;
  while (next < times.size() && times[next] <= s.t) {  // outputs at the current point
    if (!s.have_last_output || s.last_output_t < times[next]) {
      out.t = times[next];
      out.y = s.y_last;
      out.yp = s.yp_last;
      deliver(out);
    }
    ++next;
  }
  if (s.restart_pending) s.restart_at_last_output();  // a terminal event stopped inside the last step
  if (s.event_values_stale) s.refresh_event_values();
  if (!s.start_events_checked) {  // conditions that fail at the initial point (Event::met_below_at_start)
    s.start_events_checked = true;
    for (std::size_t k = 0; k < s.user_events.size(); ++k) {
      const Event& e = s.user_events[k];
      if (!e.met_below_at_start || !(s.event_last[k] < 0)) continue;
      s.hits.push_back({e.name, s.t, s.y_last, s.yp_last});
      if (e.terminal) {  // the first terminal condition that fails ends the run (Event::met_below_at_start)
        emit_last_accepted();
        return;
      }
    }
  }
  if (next == times.size()) return;
  s.check(IDASetStopTime(s.ida, t_final), "setting the stop time");
  if (s.choose_first_step) s.set_first_step(times[next] > s.t ? times[next] : t_final);

  try {
    while (next < times.size()) {
      if (s.total().steps >= s.options.max_steps)
        throw base::SolverError(base::FailureKind::too_many_steps, s.t,
                                "the step limit (" + std::to_string(s.options.max_steps) +
                                    " steps) was reached at t = " + base::number_text(s.t, 15) +
                                    " before t = " + base::number_text(t_final, 15));
      double tret = s.t;
      const double t_before = s.t;
      const int flag = IDASolve(s.ida, t_final, &tret, s.y, s.yp, IDA_ONE_STEP);
      if (flag < 0 && s.retry_first_step(flag, t_final)) continue;
      if (flag < 0) s.fail(flag, "the integration step");
      s.first_step_pending = false;

      // The user events' zeros in the step; the run ends at the first terminal one.
      const std::vector<EventRoot> roots = s.scan_events(t_before, tret, dky);
      double t_stop = INFINITY;
      for (const EventRoot& r : roots)
        if (s.user_events[static_cast<std::size_t>(r.event)].terminal) {
          t_stop = r.t;
          break;
        }
      if (t_stop < tret) {  // outputs up to the stop, then the stop itself, from the polynomial
        while (next < times.size() && times[next] <= t_stop) {
          s.interpolate(times[next], dky);
          out.t = times[next];
          out.y = s.interp_y;
          out.yp = s.interp_yp;
          deliver(out);
          ++next;
        }
        for (const EventRoot& r : roots)
          if (r.t <= t_stop) {
            s.interpolate(r.t, dky);
            s.hits.push_back({s.user_events[static_cast<std::size_t>(r.event)].name, r.t, s.interp_y, s.interp_yp});
          }
        s.interpolate(t_stop, dky);
        if (!s.have_last_output || s.last_output_t < t_stop) {
          out.t = t_stop;
          out.y = s.interp_y;
          out.yp = s.interp_yp;
          deliver(out);
        }
        // IDA stands at tret: the next integrate() or input change restarts at the stop.
        s.remember(tret);
        s.t = t_stop;
        s.y_last = s.interp_y;
        s.yp_last = s.interp_yp;
        s.restart_pending = true;
        s.event_values_stale = true;
        progress.update(t_stop);
        return;
      }
      for (const EventRoot& r : roots) {  // non-terminal events, or a terminal one at the step's end
        if (r.t == tret) {
          s.hits.push_back({s.user_events[static_cast<std::size_t>(r.event)].name, r.t,
                            std::vector<double>(s.y.data(), s.y.data() + n),
                            std::vector<double>(s.yp.data(), s.yp.data() + n)});
        } else {
          s.interpolate(r.t, dky);
          s.hits.push_back({s.user_events[static_cast<std::size_t>(r.event)].name, r.t, s.interp_y, s.interp_yp});
        }
      }

      // Outputs inside the step just taken, from IDA's interpolating polynomial.
      while (next < times.size() && times[next] <= tret) {
        if (times[next] == tret) {
          emit_current(tret);
        } else {
          s.check(IDAGetDky(s.ida, times[next], 0, dky), "interpolating the output");
          out.t = times[next];
          out.y.assign(dky.data(), dky.data() + n);
          s.check(IDAGetDky(s.ida, times[next], 1, dky), "interpolating the output");
          out.yp.assign(dky.data(), dky.data() + n);
          deliver(out);
        }
        ++next;
      }
      s.remember(tret);
      progress.update(tret);
      if (s.options.stop_requested && s.options.stop_requested())
        throw base::SolverError(base::FailureKind::stopped, tret,
                                "the run was stopped at t = " + base::number_text(tret, 15));
      double h_last = 0;
      IDAGetLastStep(s.ida, &h_last);
      s.tiny_steps = std::abs(h_last) < kTinyStep * std::max(1.0, std::abs(tret)) ? s.tiny_steps + 1 : 0;
      if (s.tiny_steps >= kCollapseSteps) s.fail(kStepSizeCollapse, "the integration");

      if (t_stop == tret) {  // a terminal event at the step's end
        if (!s.have_last_output || s.last_output_t < tret) emit_current(tret);
        return;
      }
      if (flag == IDA_ROOT_RETURN) {
        std::vector<int> found(s.n_roots(), 0);
        s.check(IDAGetRootInfo(s.ida, found.data()), "reading the singular-set monitors");
        for (int r = 0; r < s.n_roots(); ++r)
          if (found[r] != 0) {
            if (!s.have_last_output || s.last_output_t < tret) emit_current(tret);
            s.throw_singular_gradient(tret, s.root_monitors[static_cast<std::size_t>(r)], "");
          }
      } else if (flag == IDA_TSTOP_RETURN) {
        if (next < times.size() && (!s.have_last_output || s.last_output_t < tret)) emit_current(tret);
        break;
      }
      if (s.maybe_project(tret)) s.event_values_stale = true;
      if (s.options.projection != ProjectionMethod::none) s.remember(tret, false);
      if (s.event_values_stale) s.refresh_event_values();
    }
  } catch (...) {
    progress.finish();
    emit_last_accepted();
    throw;
  }
}

Statistics Integrator::statistics() const {
  const Impl& s = *impl_;
  Statistics st = s.total_with_events();
  st.projections = s.projections;
  st.initialization_seconds = s.init_seconds;
  st.integration_seconds = s.integrate_seconds;
  st.linear_solver = s.sparse ? "KLU" : "dense";
  st.jacobian = s.jacobian_kind;
  return st;
}

const std::vector<EventHit>& Integrator::events() const { return impl_->hits; }
const Model& Integrator::model() const { return impl_->model; }
const std::vector<double>& Integrator::parameters() const { return impl_->inputs.parameters(); }
const IntegratorOptions& Integrator::options() const { return impl_->options; }

std::vector<double> output_times(double t0, double t_end, int intervals) {
  std::vector<double> times(intervals + 1);
  const double span = t_end - t0;
  for (int i = 0; i <= intervals; ++i) {
    const double s = static_cast<double>(i) / intervals;
    // span * i overflows first for t_end near DBL_MAX (1e308 * 2); span itself beyond it.
    times[i] = i == intervals                    ? t_end
               : std::isfinite(span * intervals) ? t0 + span * i / intervals
               : std::isfinite(span)             ? t0 + span * s
                                                 : (1 - s) * t0 + s * t_end;
  }
  return times;
}

std::optional<std::size_t> collapsed_output_time(const std::vector<double>& times) {
  for (std::size_t i = 1; i < times.size(); ++i)
    if (!(times[i] > times[i - 1])) return i;
  return std::nullopt;
}

}  // namespace nhc::runtime
