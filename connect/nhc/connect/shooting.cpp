// Shooting for boundary-value problems (shooting.hpp, docs/connect.md).
#include "nhc/connect/shooting.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "nhc/base/number_text.hpp"

namespace nhc::connect {

namespace {

using runtime::SensitivityParameter;

/// The unknowns: the free values of segment 0, then for each inner node the independent
/// differential states (those the hidden constraints do not fix). The residual: for each inner
/// node the continuity defect of the independent states, then the target conditions.
struct Layout {
  int segments = 1;
  std::vector<double> nodes;     ///< t_0 < t_1 < … < t_K = T
  std::vector<int> free;         ///< segment 0's unknowns (state indices)
  std::vector<int> independent;  ///< each inner node's unknowns (state indices)
  int conditions = 0;

  int nf() const { return static_cast<int>(free.size()); }
  int m() const { return static_cast<int>(independent.size()); }
  int unknowns() const { return nf() + (segments - 1) * m(); }
  int rows() const { return (segments - 1) * m() + conditions; }
  int column(int segment) const { return segment == 0 ? 0 : nf() + (segment - 1) * m(); }
  const std::vector<int>& unknown_states(int segment) const { return segment == 0 ? free : independent; }
};

struct Evaluation {
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  Eigen::VectorXd scale;              ///< 1 + |target| per row (continuity rows: 1 + |node value|)
  Eigen::MatrixXd chain;              ///< ∂(targets)/∂(segment 0's free values) through all segments
  std::vector<runtime::Sample> ends;  ///< each segment's end point
  double miss() const { return r.size() ? r.cwiseAbs().maxCoeff() : 0.0; }
  bool converged(double tolerance) const {
    for (int i = 0; i < r.size(); ++i)
      if (!(std::abs(r[i]) <= tolerance * scale[i])) return false;
    return true;
  }
};

/// Free states of `model` that the hidden constraints fix when the others are given, chosen by
/// column-pivoted QR of G restricted to `candidates`.
std::vector<int> constraint_fixed(const runtime::Model& model, const std::vector<double>& p, double t,
                                  const std::vector<double>& y, const std::vector<int>& candidates) {
  const int m = model.n_hidden();
  if (m == 0 || candidates.empty()) return {};
  Eigen::MatrixXd G(m, model.n_states());
  model.table().hidden_constraints_jacobian(t, y.data(), p.data(), G.data());
  Eigen::MatrixXd A(m, static_cast<int>(candidates.size()));
  for (size_t k = 0; k < candidates.size(); ++k) A.col(static_cast<int>(k)) = G.col(candidates[k]);
  if (!A.allFinite()) return {};
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
  qr.setThreshold(1e-10);
  std::vector<int> fixed;
  for (int k = 0; k < qr.rank(); ++k)
    fixed.push_back(candidates[static_cast<size_t>(qr.colsPermutation().indices()[k])]);
  return fixed;
}

class Shooter {
 public:
  explicit Shooter(const ShootingProblem& problem) : problem_(problem) {
    p_ = problem.parameters.empty() ? problem.model.default_parameters() : problem.parameters;
    validate();
    layout_.segments = problem.segments;
    const double t0 = problem.initial.t0;
    for (int j = 0; j <= problem.segments; ++j)
      layout_.nodes.push_back(j == problem.segments ? problem.t_end : t0 + (problem.t_end - t0) * j / problem.segments);
    layout_.free = problem.free_states;
    layout_.conditions = static_cast<int>(problem.conditions.size());
  }

  ShootingResult solve();

 private:
  void validate() const {
    const runtime::Model& model = problem_.model;
    if (model.n_inputs() > 0)  // the shooting Newton needs the sensitivities, which inputs exclude
      throw base::ModelError("boundary-value problems of a model with inputs (" + model.input_name(0) +
                             (model.n_inputs() > 1 ? ", …" : "") + ") are not supported");
    if (!(problem_.t_end > problem_.initial.t0)) throw std::invalid_argument("T must be after t0");
    if (problem_.conditions.empty()) throw std::invalid_argument("no target conditions");
    if (problem_.free_states.empty()) throw std::invalid_argument("no free initial values");
    if (problem_.segments < 1) throw std::invalid_argument("segments must be at least 1");
    for (size_t k = 0; k < problem_.free_states.size(); ++k) {
      const int i = problem_.free_states[k];
      if (i < 0 || i >= model.n_states() || !model.is_differential(i))
        throw std::invalid_argument("free value " + std::to_string(i) + " is not a differential state");
      for (size_t l = 0; l < k; ++l)
        if (problem_.free_states[l] == i) throw std::invalid_argument(free_value_name(model, i) + " is free twice");
    }
  }

  runtime::InitialState segment_initial(const Eigen::VectorXd& x, int segment,
                                        const std::vector<runtime::Sample>& ends) const {
    runtime::InitialState s;
    if (segment == 0) {
      s = problem_.initial;
      s.given.resize(s.y.size(), false);
    } else {  // guesses from the previous segment's end, the independent states from x
      const runtime::Sample& before = ends[static_cast<size_t>(segment - 1)];
      s.t0 = layout_.nodes[static_cast<size_t>(segment)];
      s.y = before.y;
      s.yp = before.yp;
      s.given.assign(s.y.size(), false);
    }
    const std::vector<int>& states = layout_.unknown_states(segment);
    for (size_t k = 0; k < states.size(); ++k) {
      s.y[static_cast<size_t>(states[k])] = x[layout_.column(segment) + static_cast<int>(k)];
      s.given[static_cast<size_t>(states[k])] = true;
    }
    return s;
  }

  std::vector<SensitivityParameter> thetas(int segment) const {
    std::vector<SensitivityParameter> out;
    for (int state : layout_.unknown_states(segment))
      out.push_back({SensitivityParameter::Kind::initial_value, state, free_value_name(problem_.model, state), {}, 0});
    return out;
  }

  /// r(x), its Jacobian, and the chain ∂targets/∂free through all segments.
  Evaluation evaluate(const Eigen::VectorXd& x) const {
    Evaluation e;
    const int rows = layout_.rows(), m = layout_.m();
    e.r.setZero(rows);
    e.J.setZero(rows, layout_.unknowns());
    e.scale.setOnes(rows);
    Eigen::MatrixXd chain;  // ∂(end state)/∂(free values), all states
    for (int j = 0; j < layout_.segments; ++j) {
      runtime::SensitivityIntegrator integrator(problem_.model, p_, thetas(j), problem_.integrator);
      const double ta = layout_.nodes[static_cast<size_t>(j)], tb = layout_.nodes[static_cast<size_t>(j) + 1];
      integrator.initialize(segment_initial(x, j, e.ends), tb);
      runtime::SensitivitySample end;
      integrator.integrate({ta, tb}, [&](const runtime::SensitivitySample& s) { end = s; });
      if (!(end.t == tb)) throw base::SolverError(base::FailureKind::other, end.t, "the shooting run stopped early");
      e.ends.push_back(end.state());
      const int n = problem_.model.n_states();
      Eigen::MatrixXd S(n, static_cast<int>(end.s.size()));  // ∂y(t_b)/∂(this segment's unknowns)
      for (int k = 0; k < S.cols(); ++k) S.col(k) = Eigen::VectorXd::Map(end.s[static_cast<size_t>(k)].data(), n);
      if (j == 0) {
        chain = S;
      } else {
        Eigen::MatrixXd from_independent(m, chain.cols());
        for (int a = 0; a < m; ++a) from_independent.row(a) = chain.row(layout_.independent[static_cast<size_t>(a)]);
        chain = S * from_independent;
      }
      const int row = j * m, col = layout_.column(j);
      if (j + 1 < layout_.segments) {  // continuity: y_j(t_{j+1})[I] − z_{j+1} = 0
        for (int a = 0; a < m; ++a) {
          const int state = layout_.independent[static_cast<size_t>(a)];
          const double z = x[layout_.column(j + 1) + a];
          e.r[row + a] = end.y[static_cast<size_t>(state)] - z;
          e.scale[row + a] = 1 + std::abs(z);
          e.J.block(row + a, col, 1, S.cols()) = S.row(state);
          e.J(row + a, layout_.column(j + 1) + a) = -1.0;
        }
      } else {
        for (int c = 0; c < layout_.conditions; ++c) {
          const Condition& cond = problem_.conditions[static_cast<size_t>(c)];
          e.r[row + c] = end.y[static_cast<size_t>(cond.state)] - cond.value;
          e.scale[row + c] = 1 + std::abs(cond.value);
          e.J.block(row + c, col, 1, S.cols()) = S.row(cond.state);
        }
      }
    }
    e.chain.resize(layout_.conditions, layout_.nf());
    for (int c = 0; c < layout_.conditions; ++c)
      e.chain.row(c) = chain.row(problem_.conditions[static_cast<size_t>(c)].state);
    return e;
  }

  /// The free values whose column of ∂targets/∂free vanishes, by name.
  std::vector<std::string> uninfluential(const Evaluation& e) const {
    std::vector<std::string> names;
    const double size = std::max(1.0, e.chain.cwiseAbs().maxCoeff());
    for (int k = 0; k < layout_.nf(); ++k)
      if (e.chain.col(k).cwiseAbs().maxCoeff() <= 1e-8 * size)
        names.push_back(free_value_name(problem_.model, layout_.free[static_cast<size_t>(k)]));
    return names;
  }

  std::vector<double> free_values(const Eigen::VectorXd& x) const {
    return std::vector<double>(x.data(), x.data() + layout_.nf());
  }

  std::string history_text(const std::vector<Iteration>& history) const {
    std::ostringstream os;
    os << "iteration history (miss, step):";
    for (const Iteration& it : history)
      os << " " << it.number << ": " << base::number_text(it.miss, 3) << " (" << base::number_text(it.step, 3) << ")";
    return os.str();
  }

  [[noreturn]] void fail_stalled(const Evaluation& e, const Eigen::VectorXd& best, double best_miss, int rank,
                                 const std::vector<Iteration>& history) const {
    const int full = std::min(layout_.rows(), layout_.unknowns());
    std::ostringstream os;
    if (rank < full) {
      const std::vector<std::string> names = uninfluential(e);
      os << "the shooting Jacobian is singular (rank " << rank << " of " << full << "): ";
      if (!names.empty()) {
        for (size_t k = 0; k < names.size(); ++k) os << (k ? ", " : "") << names[k];
        os << (names.size() == 1 ? " does" : " do") << " not influence the target";
      } else {
        os << "the free values influence the target only in combination";
      }
      os << "; best miss " << base::number_text(best_miss, 6) << ". " << history_text(history);
      throw ShootingFailure(ShootingFailure::Kind::singular, os.str(), history, names, free_values(best));
    }
    os << "Newton's method stalls: no step reduces the miss, the best miss is " << base::number_text(best_miss, 6)
       << " (the target may be unreachable in this model). " << history_text(history);
    throw ShootingFailure(ShootingFailure::Kind::no_convergence, os.str(), history, {}, free_values(best));
  }

  std::vector<runtime::Sample> trajectory(const Eigen::VectorXd& x, const Evaluation& e,
                                          runtime::Statistics& last) const {
    std::vector<runtime::Sample> samples;
    const int per_segment = std::max(1, problem_.outputs / layout_.segments);
    for (int j = 0; j < layout_.segments; ++j) {
      const double ta = layout_.nodes[static_cast<size_t>(j)], tb = layout_.nodes[static_cast<size_t>(j) + 1];
      const runtime::RunResult run = runtime::simulate(problem_.model, p_, segment_initial(x, j, e.ends),
                                                       runtime::output_times(ta, tb, per_segment), problem_.integrator);
      if (run.failure) throw *run.failure;
      samples.insert(samples.end(), run.samples.begin() + (j > 0 && !run.samples.empty() ? 1 : 0), run.samples.end());
      last = run.statistics;
    }
    return samples;
  }

  const ShootingProblem& problem_;
  std::vector<double> p_;
  Layout layout_;
};

ShootingResult Shooter::solve() {
  // Inner nodes: the independent states, their starting values from one run of the guess.
  Eigen::VectorXd x(layout_.nf());
  for (int k = 0; k < layout_.nf(); ++k)
    x[k] = problem_.initial.y[static_cast<size_t>(layout_.free[static_cast<size_t>(k)])];
  if (layout_.segments > 1) {
    std::vector<int> differential;
    for (int i = 0; i < problem_.model.n_states(); ++i)
      if (problem_.model.is_differential(i)) differential.push_back(i);
    runtime::InitialState guess = segment_initial(x, 0, {});
    const runtime::RunResult run = runtime::simulate(problem_.model, p_, guess, layout_.nodes, problem_.integrator);
    if (run.failure || run.samples.size() != layout_.nodes.size())
      throw run.failure
          ? *run.failure
          : base::SolverError(base::FailureKind::other, problem_.initial.t0, "the starting guess does not reach T");
    const std::vector<int> fixed =
        constraint_fixed(problem_.model, p_, run.samples[1].t, run.samples[1].y, differential);
    for (int i : differential)
      if (std::find(fixed.begin(), fixed.end(), i) == fixed.end()) layout_.independent.push_back(i);
    x.conservativeResize(layout_.unknowns());
    for (int j = 1; j < layout_.segments; ++j)
      for (int a = 0; a < layout_.m(); ++a)
        x[layout_.column(j) + a] =
            run.samples[static_cast<size_t>(j)].y[static_cast<size_t>(layout_.independent[static_cast<size_t>(a)])];
  }

  ShootingResult result;
  result.minimum_norm = layout_.unknowns() > layout_.rows();
  result.least_squares = layout_.unknowns() < layout_.rows();
  Evaluation e = evaluate(x);
  result.history.push_back({0, e.miss(), 0.0, 0});
  for (int iteration = 1;; ++iteration) {
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(e.J);
    cod.setThreshold(1e-10);
    const int rank = static_cast<int>(cod.rank());
    result.history.back().rank = rank;
    if (e.converged(problem_.tolerance)) break;
    if (iteration > problem_.max_iterations) {
      std::ostringstream os;
      os << "Newton's method did not converge in " << problem_.max_iterations << " iterations; best miss "
         << base::number_text(e.miss(), 6) << ". " << history_text(result.history);
      throw ShootingFailure(ShootingFailure::Kind::no_convergence, os.str(), result.history, {}, free_values(x));
    }
    // J⁺ r: the Newton step, minimum-norm (more unknowns) or least-squares (more conditions).
    const Eigen::VectorXd dx = cod.solve(-e.r);
    const double norm = e.r.norm();
    bool accepted = false;
    double alpha = 1.0;
    for (int half = 0; half < 12 && !accepted; ++half, alpha *= 0.5) {
      try {
        Evaluation trial = evaluate(x + alpha * dx);
        if (trial.r.norm() < (1 - 1e-4 * alpha) * norm) {  // sufficient decrease (Armijo)
          x += alpha * dx;
          e = std::move(trial);
          accepted = true;
          result.history.push_back({iteration, e.miss(), alpha, 0});
        }
      } catch (const base::SolverError&) {
        // the integration failed at the trial point: a shorter step
      }
    }
    if (!accepted) fail_stalled(e, x, e.miss(), rank, result.history);
  }
  result.values = free_values(x);
  result.miss = e.miss();
  result.trajectory = trajectory(x, e, result.last_run);
  return result;
}

}  // namespace

std::string free_value_name(const runtime::Model& model, int state) { return model.state_name(state) + "(0)"; }

std::vector<int> default_free_states(const runtime::Model& model, const std::vector<double>& parameters,
                                     const runtime::InitialState& initial) {
  const std::vector<double> p = parameters.empty() ? model.default_parameters() : parameters;
  std::vector<int> candidates;
  for (int i = 0; i < model.n_states(); ++i)
    if (model.is_differential(i) &&
        !(i < static_cast<int>(initial.given.size()) && initial.given[static_cast<size_t>(i)]))
      candidates.push_back(i);
  const std::vector<int> fixed = constraint_fixed(model, p, initial.t0, initial.y, candidates);
  std::vector<int> free;
  for (int i : candidates)
    if (std::find(fixed.begin(), fixed.end(), i) == fixed.end()) free.push_back(i);
  return free;
}

ShootingResult connect(const ShootingProblem& problem) { return Shooter(problem).solve(); }

}  // namespace nhc::connect
