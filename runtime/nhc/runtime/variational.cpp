// The variational integrator's run loop (variational.hpp, docs/variational.md).
#include "nhc/runtime/variational.hpp"

#include "nhc/base/clock.hpp"
#include "nhc/base/number_text.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace nhc::runtime {

namespace {

/// A node of the discrete trajectory: q_k, its velocity and acceleration, the multipliers.
struct Node {
  double t = 0;
  std::vector<double> q, v, a, lambda;
};

/// Where the states of a model hold q, q', q'' and λ (-1 where it holds none).
struct StateLayout {
  int n = 0, g = 0;
  std::vector<int> variable, order;  // per state

  explicit StateLayout(const Model& model) : n(model.n_coordinates()), g(model.n_multipliers()) {
    for (int i = 0; i < model.n_states(); ++i) {
      variable.push_back(model.table().state_variable[i]);
      order.push_back(model.table().state_order[i]);
    }
  }

  /// The initial node from IDA's consistent point.
  Node node(const Sample& s) const {
    Node x;
    x.t = s.t;
    x.q.assign(static_cast<std::size_t>(n), 0.0);
    x.v = x.a = x.q;
    x.lambda.assign(static_cast<std::size_t>(g), 0.0);
    for (std::size_t i = 0; i < variable.size(); ++i) {
      const int j = variable[i];
      if (j >= n) {
        if (order[i] == 0) x.lambda[static_cast<std::size_t>(j - n)] = s.y[i];
        continue;
      }
      const auto c = static_cast<std::size_t>(j);
      if (order[i] == 0) x.q[c] = s.y[i];
      if (order[i] == 0 && x.v[c] == 0.0) x.v[c] = s.yp[i];
      if (order[i] == 1) x.v[c] = s.y[i], x.a[c] = s.yp[i];
    }
    return x;
  }

  /// The sample at t in [a.t, b.t]: q by the cubic Hermite polynomial through (q, v) at both
  /// nodes, v its derivative, q'' and λ linear (a node itself at s = 0 and s = 1).
  void sample(double t, const Node& a, const Node& b, Sample& out) const {
    const double h = b.t - a.t;
    const double s = h > 0 ? std::clamp((t - a.t) / h, 0.0, 1.0) : 0.0;
    const double s2 = s * s, s3 = s2 * s;
    const double h00 = 2 * s3 - 3 * s2 + 1, h10 = s3 - 2 * s2 + s, h01 = -2 * s3 + 3 * s2, h11 = s3 - s2;
    const double d00 = (6 * s2 - 6 * s) / h, d10 = 3 * s2 - 4 * s + 1, d01 = -d00, d11 = 3 * s2 - 2 * s;
    out.t = t;
    out.y.assign(variable.size(), 0.0);
    out.yp.assign(variable.size(), 0.0);
    for (std::size_t i = 0; i < variable.size(); ++i) {
      const int j = variable[i];
      if (j >= n) {
        const auto c = static_cast<std::size_t>(j - n);
        if (order[i] == 0) out.y[i] = (1 - s) * a.lambda[c] + s * b.lambda[c];
        continue;
      }
      const auto c = static_cast<std::size_t>(j);
      const double q = h00 * a.q[c] + h10 * h * a.v[c] + h01 * b.q[c] + h11 * h * b.v[c];
      const double v = h > 0 ? d00 * a.q[c] + d10 * a.v[c] + d01 * b.q[c] + d11 * b.v[c] : a.v[c];
      const double acc = (1 - s) * a.a[c] + s * b.a[c];
      const double values[] = {q, v, acc, 0.0};
      const int o = std::min(order[i], 2);
      out.y[i] = values[o];
      out.yp[i] = values[o + 1];
    }
  }
};

/// The state at a step's midpoint from q_k and the step's unknowns x = (Δq, λ): q_k + Δq/2, the
/// midpoint rule's velocity Δq/h, the acceleration (Δq − Δq_previous)/h² and λ. A feedback input
/// u(t, y) is evaluated there, where the step evaluates the forces.
Node midpoint_node(double t, double h, const std::vector<double>& q, const std::vector<double>& dq_previous,
                   const Eigen::VectorXd& x, int g) {
  Node node;
  node.t = t + h / 2;
  const std::size_t n = q.size();
  node.q.resize(n);
  node.v.resize(n);
  node.a.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double dq = x[static_cast<Eigen::Index>(i)];
    node.q[i] = q[i] + dq / 2;
    node.v[i] = dq / h;
    node.a[i] = (dq - dq_previous[i]) / (h * h);
  }
  node.lambda.assign(x.data() + n, x.data() + n + g);
  return node;
}

/// Passes of a step over a feedback input before it must have settled (each a Newton solve,
/// warm-started; the inputs' change shrinks by about h times their sensitivity per pass).
constexpr int kMaxInputPasses = 50;

/// Corrections up to this many times the Newton tolerance that stop shrinking are rounding noise.
constexpr double kRoundingLevelFactor = 1000;

/// One Newton solve of the generated step r(x) = 0 (dense LU; the step is small: n + g unknowns).
class StepSolver {
 public:
  StepSolver(const Model& model, const VariationalOptions& options)
      : model_(model),
        table_(model.table()),
        options_(options),
        n_(model.n_coordinates()),
        size_(model.n_coordinates() + model.n_multipliers()),
        r_(size_),
        dx_(size_),
        J_(size_, size_),
        lu_(size_) {}

  /// Solves for x (its guess in, the solution out); throws SolverError at a failure.
  void solve(double t, double h, double w, const double* dq_previous, const double* q, const double* m, const double* p,
             Eigen::VectorXd& x, Statistics& st) {
    double last_correction = 0, previous_correction = 0;
    for (int iteration = 0; iteration < options_.max_newton_iterations; ++iteration) {
      residual(t, h, w, dq_previous, q, m, x, p, st);
      table_.variational_jacobian(t, h, w, dq_previous, q, m, x.data(), p, J_.data());
      ++st.jacobian_evaluations;
      if (!J_.allFinite())
        throw base::SolverError(
            base::FailureKind::nonfinite_residual, t,
            "the Jacobian of the variational step from t = " + base::number_text(t, 12) + " is not finite");
      lu_.compute(J_);
      dx_ = lu_.solve(-r_);
      ++st.nonlinear_iterations;
      if (!dx_.allFinite() || lu_.matrixLU().diagonal().cwiseAbs().minCoeff() == 0.0)
        throw base::SolverError(base::FailureKind::singular_iteration_matrix, t,
                                "the Jacobian of the variational step from t = " + base::number_text(t, 12) +
                                    " is singular (a constraint gradient vanishing there, or a step h = " +
                                    base::number_text(h, 12) + " at which the discrete equations degenerate)");
      x += dx_;
      previous_correction = last_correction;
      last_correction = 0;
      for (int i = 0; i < size_; ++i)
        last_correction = std::max(last_correction, std::abs(dx_[i]) / (1 + std::abs(x[i])));
      if (last_correction <= options_.newton_tolerance) return;
      // Rounding level reached a little above the tolerance: the corrections no longer shrink
      // (quadratic convergence would divide them by far more than 2), and are tiny.
      if (iteration > 0 && last_correction > previous_correction / 2 &&
          last_correction <= kRoundingLevelFactor * options_.newton_tolerance)
        return;
    }
    ++st.nonlinear_failures;
    throw base::SolverError(
        base::FailureKind::convergence, t,
        "Newton's method did not converge on the variational step " + std::to_string(st.steps + 1) +
            " from t = " + base::number_text(t, 12) + " to " + base::number_text(t + h, 12) +
            " (step h = " + base::number_text(h, 12) + ", " + std::to_string(options_.max_newton_iterations) +
            " iterations, last relative correction " + base::number_text(last_correction, 12) + ", largest residual " +
            largest_residual() + "); try a smaller step (--step) or IDA (--integrator ida)");
  }

  /// r(x) into r(), with the check that it is finite.
  void residual(double t, double h, double w, const double* dq_previous, const double* q, const double* m,
                const Eigen::VectorXd& x, const double* p, Statistics& st) {
    table_.variational_residual(t, h, w, dq_previous, q, m, x.data(), p, r_.data());
    ++st.residual_evaluations;
    for (int i = 0; i < size_; ++i)
      if (!std::isfinite(r_[i]))
        throw base::SolverError(
            base::FailureKind::nonfinite_residual, t,
            "the variational step from t = " + base::number_text(t, 12) + " gives a non-finite " + name(i));
  }

  const Eigen::VectorXd& r() const { return r_; }

 private:
  std::string name(int i) const { return i < n_ ? "R_" + model_.variable_name(i) : "f" + std::to_string(i - n_ + 1); }
  std::string largest_residual() const {
    Eigen::Index at = 0;
    const double value = r_.cwiseAbs().maxCoeff(&at);
    return name(static_cast<int>(at)) + " = " + base::number_text(value, 12);
  }

  const Model& model_;
  const nhc_model_table& table_;
  const VariationalOptions& options_;
  int n_, size_;
  Eigen::VectorXd r_, dx_;
  Eigen::MatrixXd J_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
};

}  // namespace

VariationalOptions variational_options(double step, long max_steps, const IntegratorOptions& ida) {
  VariationalOptions options;
  options.step = step;
  options.max_steps = max_steps;
  options.initialization = ida;
  options.progress = ida.progress;
  options.stop_requested = ida.stop_requested;
  return options;
}

long variational_steps_needed(double t0, double t_end, double h) {
  const double intervals = (t_end - t0) / h;
  if (!std::isfinite(intervals) || intervals > 1e15) return -1;
  // A t_end within rounding of a node is that node.
  return std::max(1L, static_cast<long>(std::ceil(intervals * (1 - 1e-12))));
}

bool variational_step_fits(double t0, double t_end, double h) { return (t_end - t0) / h >= 2 * (1 - 1e-12); }

VariationalRun simulate_variational(const Model& model, const std::vector<double>& p, const InitialState& initial,
                                    const std::vector<double>& times, const VariationalOptions& options,
                                    const InputFunction& inputs) {
  if (!model.has_variational_step())
    throw base::ModelError("model " + model.scene_name() + "_" + model.model_name() +
                           " was generated without the variational step (nhc generate --variational)");
  if (!(options.step > 0) || !std::isfinite(options.step))
    throw std::invalid_argument("the variational step must be positive, not " + base::number_text(options.step, 12));
  if (times.empty()) throw std::invalid_argument("no output times");
  const double t_end = times.back();
  if (!variational_step_fits(initial.t0, t_end, options.step))
    throw std::invalid_argument("the variational step " + base::number_text(options.step, 12) +
                                " does not fit the run from t = " + base::number_text(initial.t0, 12) + " to " +
                                base::number_text(t_end, 12) + " twice");
  // N equal steps of at most options.step that end on t_end (docs/variational.md, "Samples").
  const long steps = variational_steps_needed(initial.t0, t_end, options.step);
  const double h = steps > 0 ? (t_end - initial.t0) / static_cast<double>(steps) : options.step;
  VariationalRun out;
  RunResult& result = out.run;
  Statistics& st = result.statistics;
  st.linear_solver = "dense";
  st.jacobian = "generated dense (variational step)";

  const std::vector<double> parameters = p.empty() ? model.default_parameters() : p;
  const auto init_start = base::Clock::now();
  {
    Integrator integrator(model, parameters, options.initialization);
    if (inputs) integrator.set_inputs(inputs);
    try {
      result.initial = integrator.initialize(initial, initial.t0 + h);
    } catch (const base::SolverError& e) {
      result.failure = e;
      st.initialization_seconds = base::seconds_since(init_start);
      return out;
    }
  }
  st.initialization_seconds = base::seconds_since(init_start);
  const double t0 = result.initial.t;
  if (steps < 0 || steps > options.max_steps) {
    result.failure =
        base::SolverError(base::FailureKind::too_many_steps, t0,
                          "a fixed step h = " + base::number_text(h, 12) + " from t = " + base::number_text(t0, 12) +
                              " to " + base::number_text(times.back(), 12) + " takes " +
                              (steps < 0 ? std::string("too many") : std::to_string(steps)) +
                              " steps, more than the limit of " + std::to_string(options.max_steps));
    return out;
  }

  const auto start = base::Clock::now();
  const nhc_model_table& table = model.table();
  const StateLayout layout(model);
  const int n = layout.n, g = layout.g;
  const auto nn = static_cast<std::size_t>(n);
  InputValues values(model, parameters);
  if (inputs) values.set_function(inputs);
  StepSolver solver(model, options);
  ProgressReporter progress(options.progress, t0, times.back());

  Node previous = layout.node(result.initial);  // the last completed node
  // q_k summed from the increments with Kahan's compensation: a million steps add no more
  // rounding to q than a few.
  std::vector<double> dq_previous(nn), q = previous.q, q_compensation(nn, 0.0), m(nn), m_next(nn), used_inputs,
                                       dq_before, lambda_before;
  const std::vector<double>& y0 = result.initial.y;
  for (std::size_t i = 0; i < nn; ++i) dq_previous[i] = h * previous.v[i];
  table.momentum(t0, y0.data(), values.at(t0, y0.data()), m.data());
  Eigen::VectorXd x(n + g);
  for (int i = 0; i < n; ++i) x[i] = dq_previous[static_cast<std::size_t>(i)];
  for (int a = 0; a < g; ++a) x[n + a] = previous.lambda[static_cast<std::size_t>(a)];

  std::size_t next_time = 0;
  Sample sample, midpoint_sample;
  const auto emit_through = [&](const Node& a, const Node& b) {
    const double slack = 1e-12 * std::max(1.0, std::abs(b.t));
    for (; next_time < times.size() && times[next_time] <= b.t + slack; ++next_time) {
      layout.sample(std::max(times[next_time], a.t), a, b, sample);
      sample.t = times[next_time];
      const double* pu = values.at(sample.t, sample.y.data());
      sample.u.assign(pu + model.n_parameters(), pu + model.n_parameters() + model.n_inputs());
      result.samples.push_back(sample);
    }
  };
  try {
    for (long k = 0; k < steps; ++k) {
      const double t = t0 + static_cast<double>(k) * h;
      if (options.stop_requested && options.stop_requested())
        throw base::SolverError(base::FailureKind::stopped, t,
                                "stopped at t = " + base::number_text(t, 12) + " (interrupted)");
      const double w = k == 0 ? 0.5 : 1.0;  // the first step meets half the impulse at t0
      // Inputs at the step's midpoint state (second order for a feedback law u(t, y) too): first
      // from the increment x predicts, then from the solution's, until they settle.
      const auto inputs_at_midpoint = [&] {
        const Node middle = midpoint_node(t, h, q, dq_previous, x, g);
        layout.sample(middle.t, middle, middle, midpoint_sample);
        return values.at(middle.t, midpoint_sample.y.data());
      };
      const double* pk = model.n_inputs() > 0 ? inputs_at_midpoint() : values.at(t + h / 2, nullptr);
      for (int pass = 1;; ++pass) {
        solver.solve(t, h, w, dq_previous.data(), q.data(), m.data(), pk, x, st);
        if (model.n_inputs() == 0) break;
        used_inputs.assign(pk + model.n_parameters(), pk + model.n_parameters() + model.n_inputs());
        pk = inputs_at_midpoint();
        bool settled = true;
        for (int i = 0; i < model.n_inputs(); ++i) {
          const double u = pk[model.n_parameters() + i], before = used_inputs[static_cast<std::size_t>(i)];
          settled = settled && std::abs(u - before) <= options.newton_tolerance * (1 + std::abs(u));
        }
        if (settled) break;
        if (pass == kMaxInputPasses)
          throw base::SolverError(base::FailureKind::convergence, t,
                                  "the inputs did not settle on the variational step " + std::to_string(st.steps + 1) +
                                      " from t = " + base::number_text(t, 12) + " to " + base::number_text(t + h, 12) +
                                      " (step h = " + base::number_text(h, 12) +
                                      "): a feedback law u(t, y) that changes this fast along the " +
                                      "step needs a smaller --step");
      }
      solver.residual(t, h, w, dq_previous.data(), q.data(), m.data(), x, pk, st);
      for (int a = 0; a < g; ++a)
        out.max_discrete_constraint = std::max(out.max_discrete_constraint, std::abs(solver.r()[n + a]));
      table.variational_momentum(t, h, q.data(), x.data(), pk, m_next.data());
      ++st.steps;
      if (k > 0) {  // node k is complete: its velocity needs q_{k+1}
        Node node;
        node.t = t;
        node.q = q;
        node.v.resize(nn);
        node.a.resize(nn);
        for (std::size_t i = 0; i < nn; ++i) {
          node.v[i] = (x[static_cast<Eigen::Index>(i)] + dq_previous[i]) / (2 * h);
          node.a[i] = (x[static_cast<Eigen::Index>(i)] - dq_previous[i]) / (h * h);
        }
        node.lambda.assign(x.data() + n, x.data() + n + g);
        emit_through(previous, node);
        lambda_before = std::move(previous.lambda);
        previous = std::move(node);
      }
      dq_before = dq_previous;
      // Shift the window; the next increment is predicted equal to this one.
      for (std::size_t i = 0; i < nn; ++i) {
        const double dq = x[static_cast<Eigen::Index>(i)];
        dq_previous[i] = dq;
        const double corrected = dq - q_compensation[i], sum = q[i] + corrected;
        q_compensation[i] = (sum - q[i]) - corrected;
        q[i] = sum;
      }
      m.swap(m_next);
      progress.update(t);
    }
    // The last node, t_end itself: no step follows it, so its velocity is the second-order backward
    // difference (3 Δq_{N−1} − Δq_{N−2})/(2h), its acceleration (Δq_{N−1} − Δq_{N−2})/h² and its
    // multipliers extrapolated linearly from the two nodes before (N >= 2: variational_step_fits).
    Node last;
    last.t = t_end;
    last.q = q;
    last.v.resize(nn);
    last.a.resize(nn);
    for (std::size_t i = 0; i < nn; ++i) {
      last.v[i] = (3 * dq_previous[i] - dq_before[i]) / (2 * h);
      last.a[i] = (dq_previous[i] - dq_before[i]) / (h * h);
    }
    last.lambda.resize(static_cast<std::size_t>(g));
    for (std::size_t a = 0; a < static_cast<std::size_t>(g); ++a)
      last.lambda[a] = 2 * previous.lambda[a] - (lambda_before.empty() ? previous.lambda[a] : lambda_before[a]);
    emit_through(previous, last);
  } catch (const base::SolverError& e) {
    result.failure = e;
  }
  out.steps = st.steps;
  st.integration_seconds = base::seconds_since(start);
  return out;
}

}  // namespace nhc::runtime
