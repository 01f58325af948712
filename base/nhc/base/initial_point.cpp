#include "nhc/base/initial_point.hpp"

#include "nhc/base/number_text.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace nhc::base {

namespace {

std::string join(const std::vector<std::string>& items) {
  std::string s;
  for (std::size_t i = 0; i < items.size(); ++i) s += (i == 0 ? "" : i + 1 == items.size() ? " and " : ", ") + items[i];
  return s;
}

}  // namespace

std::string InitialPointTolerance::describe() const {
  return number_text(accept, 3) + " = atol + rtol·max(1, |y|) = " + number_text(atol, 3) + " + " +
         number_text(rtol, 3) + "·" + number_text(size, 3);
}

InitialPointTolerance initial_point_tolerance(const std::vector<double>& y, double rtol, double atol) {
  InitialPointTolerance t;
  t.rtol = rtol;
  t.atol = atol;
  for (double v : y)
    if (std::isfinite(v)) t.size = std::max(t.size, std::abs(v));
  t.solve = 1e-13 * t.size;
  t.accept = std::max(t.solve, atol + rtol * t.size);
  return t;
}

ConstraintSolveResult solve_initial_point(const ConstraintFunctions& g, double* y, const std::vector<double>& scale,
                                          const InitialPointTolerance& tolerance, int max_iterations) {
  ConstraintSolveResult r = solve_constraints(g, y, scale, tolerance.solve, max_iterations);
  if (!r.converged() && std::isfinite(r.residual_after) && r.residual_after <= tolerance.accept &&
      r.status != ConstraintSolveStatus::gradient_not_finite)
    r.status = ConstraintSolveStatus::converged;
  return r;
}

InitialPointSolve solve_or_repair_initial_point(const ConstraintFunctions& g, double* y,
                                                const std::vector<double>& scale,
                                                const std::vector<double>* repair_scale,
                                                const InitialPointTolerance& tolerance, int max_iterations) {
  InitialPointSolve out;
  out.result = solve_initial_point(g, y, scale, tolerance, max_iterations);
  if (out.result.converged() || !repair_scale) return out;
  out.repaired = true;
  out.result = solve_constraints(g, y, *repair_scale, tolerance.solve, max_iterations);
  return out;
}

std::string describe(const InconsistentInitialPoint& f) {
  std::ostringstream s;
  s << "the initial values of the " << f.model << " model violate " << f.constraint
    << " at t0 = " << number_text(f.t0, 10) << ": residual " << number_text(f.residual, 10) << " (tolerance "
    << f.tolerance.describe() << ")";
  std::vector<std::string> given;
  for (const InvolvedValue& v : f.given) given.push_back(v.name + " = " + number_text(v.value, 10));
  if (!given.empty()) s << "; it involves the given value" << (given.size() == 1 ? " " : "s ") << join(given);
  if (f.free.empty()) s << "; no value that may be changed enters it";
  else if (f.status == ConstraintSolveStatus::stalled || f.status == ConstraintSolveStatus::iteration_limit)
    s << "; Gauss–Newton did not converge for " << join(f.free);
  s << ". Give consistent values, or have them repaired to the nearest consistent point (--repair-initial)";
  return s.str();
}

}  // namespace nhc::base
