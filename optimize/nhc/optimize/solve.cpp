#include "nhc/optimize/solve.hpp"

#include <IpIpoptApplication.hpp>
#include <IpIpoptData.hpp>
#include <IpTNLP.hpp>

#include <algorithm>
#include <cmath>
#include <mutex>

#include <fmt/format.h>

#include "nhc/errors.hpp"

namespace nhc::optimize {

namespace {

using Ipopt::Index;
/// IPOPT's bound_relax_factor: the bounds IPOPT works with are widened by this times
/// max(1, |bound|), and honor_original_bounds projects the result back into the variables' own
/// bounds, which moves the equations by as much: 1e-10 keeps that below constr_viol_tol (1e-9),
/// where IPOPT's default 1e-8 left violations of 7e-9 after a reported success.
constexpr double kBoundRelax = 1e-10;
using Ipopt::Number;

class Adapter : public Ipopt::TNLP {
 public:
  Adapter(HermiteSimpson& problem, const std::vector<double>& guess, const SolveOptions& options, Solution& out)
      : problem_(problem), guess_(guess), options_(options), out_(out) {}

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag, IndexStyleEnum& style) override {
    n = problem_.variables();
    m = problem_.constraints();
    nnz_jac_g = problem_.jacobian_nonzeros();
    nnz_h_lag = options_.exact_hessian ? problem_.hessian_nonzeros() : 0;  // limited memory: none asked for
    style = C_STYLE;
    return true;
  }
  bool get_bounds_info(Index, Number* x_l, Number* x_u, Index, Number* g_l, Number* g_u) override {
    problem_.variable_bounds(x_l, x_u);
    problem_.constraint_bounds(g_l, g_u);
    return true;
  }
  bool get_starting_point(Index n, bool init_x, Number* x, bool, Number*, Number*, Index, bool, Number*) override {
    if (init_x) std::copy(guess_.begin(), guess_.begin() + n, x);
    return true;
  }
  bool eval_f(Index, const Number* x, bool, Number& f) override {
    f = problem_.objective(x);
    if (!std::isfinite(f)) nonfinite(fmt::format("the objective (cost {})", f));
    return std::isfinite(f);
  }
  bool eval_grad_f(Index n, const Number* x, bool, Number* g) override {
    problem_.objective_gradient(x, g);
    const Number* bad = std::find_if(g, g + n, [](double v) { return !std::isfinite(v); });
    if (bad != g + n) nonfinite(fmt::format("the objective's derivative by variable {}", bad - g));
    return bad == g + n;
  }
  bool eval_g(Index, const Number* x, bool, Index m, Number* g) override {
    problem_.constraint_values(x, g);
    const Number* bad = std::find_if(g, g + m, [](double v) { return !std::isfinite(v); });
    if (bad != g + m) nonfinite(problem_.constraint_name(static_cast<int>(bad - g), x));
    return bad == g + m;
  }
  bool eval_jac_g(Index, const Number* x, bool, Index, Index nele, Index* rows, Index* cols, Number* values) override {
    if (!values) {
      problem_.jacobian_structure(rows, cols);
      return true;
    }
    problem_.jacobian_values(x, values);
    const bool finite = std::all_of(values, values + nele, [](double v) { return std::isfinite(v); });
    if (!finite) nonfinite("a derivative of the constraints");
    return finite;
  }
  bool eval_h(Index, const Number* x, bool, Number obj_factor, Index, const Number* lambda, bool, Index nele,
              Index* rows, Index* cols, Number* values) override {
    if (!values) {
      problem_.hessian_structure(rows, cols);
      return true;
    }
    problem_.hessian_values(x, obj_factor, lambda, values);
    return std::all_of(values, values + nele, [](double v) { return std::isfinite(v); });
  }
  bool intermediate_callback(Ipopt::AlgorithmMode, Index iter, Number obj_value, Number inf_pr, Number, Number, Number,
                             Number, Number, Number, Index, const Ipopt::IpoptData*,
                             Ipopt::IpoptCalculatedQuantities*) override {
    out_.iterations = iter;
    return !options_.progress || options_.progress(iter, obj_value, inf_pr);
  }
  void finalize_solution(Ipopt::SolverReturn status, Index n, const Number* x, const Number*, const Number*, Index m,
                         const Number*, const Number*, Number obj_value, const Ipopt::IpoptData*,
                         Ipopt::IpoptCalculatedQuantities*) override {
    out_.z.assign(x, x + n);
    out_.cost = obj_value;
    std::vector<double> g(static_cast<std::size_t>(m)), low(static_cast<std::size_t>(m)),
        high(static_cast<std::size_t>(m));
    problem_.constraint_values(x, g.data());
    problem_.constraint_bounds(low.data(), high.data());
    // How far each row is outside [low, high] (an equation: |g|); an inequality's bounds are
    // relaxed by IPOPT's bound_relax_factor (1e-8 max(1, |bound|), docs/optimize.md), which the
    // stated tolerance allows.
    out_.violation = 0;
    for (std::size_t r = 0; r < g.size(); ++r) {
      const bool equation = low[r] == high[r];
      const double lo = equation ? low[r] : low[r] - kBoundRelax * std::max(1.0, std::abs(low[r]));
      const double hi = equation ? high[r] : high[r] + kBoundRelax * std::max(1.0, std::abs(high[r]));
      const double outside = std::max({lo - g[r], g[r] - hi, 0.0});
      if (outside > out_.violation) {
        out_.violation = outside;
        out_.worst = problem_.constraint_name(static_cast<int>(r), x);
      }
    }
    out_.cost = problem_.objective(x);
    switch (status) {
      case Ipopt::SUCCESS:
        out_.status = Solution::Status::optimal;
        break;
      case Ipopt::MAXITER_EXCEEDED:
      case Ipopt::CPUTIME_EXCEEDED:
      case Ipopt::STOP_AT_ACCEPTABLE_POINT:
        out_.status = status == Ipopt::STOP_AT_ACCEPTABLE_POINT ? Solution::Status::acceptable
                                                                : Solution::Status::iteration_limit;
        out_.words = status == Ipopt::STOP_AT_ACCEPTABLE_POINT
                         ? "IPOPT stopped at a point that meets only its acceptable tolerance (1e-6), not --tolerance"
                         : "IPOPT reached its iteration limit";
        break;
      case Ipopt::LOCAL_INFEASIBILITY:
        out_.status = Solution::Status::infeasible;
        out_.words =
            "the problem is locally infeasible: IPOPT converged to a point that minimises the violation of the "
            "constraints";
        break;
      case Ipopt::RESTORATION_FAILURE:
        // Not a proof of infeasibility: a start where the constraints' gradients vanish, or a
        // badly scaled problem, ends here too.
        out_.status = Solution::Status::failed;
        out_.words =
            "IPOPT's restoration phase could not reduce the violation of the constraints (this does not show that no "
            "path exists: another start or --guess may find one)";
        break;
      case Ipopt::DIVERGING_ITERATES:
        out_.status = Solution::Status::failed;
        out_.words =
            "IPOPT's iterates diverged (a variable grew beyond 1e20): the cost may be unbounded below, or a variable "
            "needs a bound";
        break;
      case Ipopt::INVALID_NUMBER_DETECTED:
        out_.status = Solution::Status::failed;
        out_.words =
            "a function was not finite at IPOPT's iterate" + (nonfinite_.empty() ? std::string() : ": " + nonfinite_);
        break;
      case Ipopt::ERROR_IN_STEP_COMPUTATION:
        out_.status = Solution::Status::failed;
        out_.words =
            "IPOPT could not compute a step (its linear system stayed singular: conditions that repeat what the "
            "dynamics already keep?)";
        break;
      case Ipopt::TOO_FEW_DEGREES_OF_FREEDOM:
        out_.status = Solution::Status::failed;
        out_.words =
            "more conditions than unknowns (too few degrees of freedom): the boundary values repeat what the "
            "dynamics already keep";
        break;
      case Ipopt::STOP_AT_TINY_STEP:
        out_.status = Solution::Status::failed;
        out_.words =
            "IPOPT's steps became too small to make progress before its tolerance was met (try --tolerance larger)";
        break;
      case Ipopt::OUT_OF_MEMORY:
        out_.status = Solution::Status::failed;
        out_.words = "IPOPT ran out of memory";
        break;
      case Ipopt::USER_REQUESTED_STOP:
        out_.status = Solution::Status::failed;
        out_.words = "stopped on request";
        break;
      default:
        out_.status = Solution::Status::failed;
        out_.words = "IPOPT failed with an internal error or an invalid option (its status " +
                     std::to_string(static_cast<int>(status)) + ")";
    }
    // A point reported as converged (or acceptable) meets the stated violation tolerance, measured
    // here on the variables' own bounds, or it is no answer.
    const bool converged = out_.status == Solution::Status::optimal || out_.status == Solution::Status::acceptable;
    if (converged && !(out_.violation <= options_.violation_tolerance)) {
      out_.words = fmt::format("IPOPT reported {} with a constraint violation of {:.3g}, above the tolerance {:.3g}",
                               out_.status == Solution::Status::optimal ? "convergence" : "its acceptable level",
                               out_.violation, options_.violation_tolerance);
      out_.status = Solution::Status::failed;
    }
  }

 private:
  void nonfinite(const std::string& what) {
    if (nonfinite_.empty()) nonfinite_ = what;
  }

  HermiteSimpson& problem_;
  std::string nonfinite_;  ///< the first non-finite value IPOPT met, in words
  const std::vector<double>& guess_;
  const SolveOptions& options_;
  Solution& out_;
};

}  // namespace

Solution solve(HermiteSimpson& problem, const std::vector<double>& guess, const SolveOptions& options) {
  Solution solution;
  Ipopt::SmartPtr<Ipopt::TNLP> nlp = new Adapter(problem, guess, options, solution);
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->Options()->SetIntegerValue("print_level", 0);
  app->Options()->SetStringValue("sb", "yes");  // no banner on stdout
  app->Options()->SetStringValue("hessian_approximation", options.exact_hessian ? "exact" : "limited-memory");
  app->Options()->SetIntegerValue("max_iter", options.max_iterations);
  app->Options()->SetNumericValue("tol", options.tolerance);
  app->Options()->SetNumericValue("constr_viol_tol", options.violation_tolerance);
  // An acceptable-level stop loosens only the optimality test (acceptable_tol, 1e-6): its
  // violation must meet the same tolerance as a converged point (IPOPT's default allows 1e-2),
  // so that every point nhc reports meets the stated violation tolerance.
  app->Options()->SetNumericValue("acceptable_constr_viol_tol", options.violation_tolerance);
  app->Options()->SetIntegerValue("acceptable_iter", options.acceptable_iterations);
  app->Options()->SetStringValue("mu_strategy", "adaptive");
  app->Options()->SetNumericValue("bound_relax_factor", kBoundRelax);
  if (options.finite_difference_jacobian)
    app->Options()->SetStringValue("jacobian_approximation", "finite-difference-values");
  if (app->Initialize() != Ipopt::Solve_Succeeded) throw EnvironmentError("IPOPT could not be initialised");
  // MUMPS (IPOPT's linear solver, Debian's sequential build) keeps global state: one solve at a
  // time per process (Python threads may ask for several).
  static std::mutex mumps;
  const std::lock_guard<std::mutex> one_at_a_time(mumps);
  const Ipopt::ApplicationReturnStatus status = app->OptimizeTNLP(nlp);
  if (solution.z.empty())
    throw MathError("IPOPT stopped before its first iteration (status " + std::to_string(static_cast<int>(status)) +
                    ")");
  return solution;
}

}  // namespace nhc::optimize
