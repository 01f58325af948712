#pragma once
/// \file initial_point.hpp
/// \brief The one rule by which `nhc analyze` and `nhc simulate` accept initial values, and the
/// one message when they do not, so that the two commands never disagree on a scene.
///
/// Values the user did not give are solved from the hidden constraints g = 0 to
///   solve = 1e-13 · max(1, |y|)
/// (close to rounding, constraint_solver.hpp). Given values are accepted when they miss a hidden
/// constraint by at most
///   accept = atol + rtol · max(1, |y|)
/// with the run's atol and rtol ([simulate], overridden by --atol/--rtol): the accuracy the
/// integrator is asked for anyway, so typing a velocity to ten digits is enough. A larger
/// miss is an error naming the constraint, its residual, this tolerance and the given values
/// the constraint involves — the same words in both commands.

#include <string>
#include <vector>

#include "nhc/base/constraint_solver.hpp"

namespace nhc::base {

struct InitialPointTolerance {
  double rtol = 0, atol = 0;
  double size = 1;    ///< max(1, |y|)
  double solve = 0;   ///< the solver's target for the values not given
  double accept = 0;  ///< the largest residual accepted from given values
  /// "1.3e-08 = atol + rtol·max(1, |y|) = 1e-10 + 1e-08·1.25"
  std::string describe() const;
};

InitialPointTolerance initial_point_tolerance(const std::vector<double>& y, double rtol, double atol);

/// solve_constraints to tolerance.solve; a run that ends (fails) with max |g_i| <= tolerance.accept
/// counts as converged.
ConstraintSolveResult solve_initial_point(const ConstraintFunctions& g, double* y, const std::vector<double>& scale,
                                          const InitialPointTolerance& tolerance, int max_iterations = 50);

/// The outcome of solve_or_repair_initial_point.
struct InitialPointSolve {
  ConstraintSolveResult result;  ///< of the repair when one was tried, else of the first solve
  bool repaired = false;         ///< the first solve failed and the repair was tried
};

/// The one rule by which --repair-initial moves initial values, in `nhc analyze` and
/// `nhc simulate` alike: first the values not given are solved with the given ones fixed
/// (`scale`, as solve_initial_point); only when that fails and `repair_scale` is given does every
/// value with repair_scale[i] > 0 (all but those pinned by [initial] fixed) move to the nearest
/// consistent point, the minimum-norm correction from where the first solve stopped. Given values
/// that are consistent therefore stay, and a given value no violated constraint involves never moves.
InitialPointSolve solve_or_repair_initial_point(const ConstraintFunctions& g, double* y,
                                                const std::vector<double>& scale,
                                                const std::vector<double>* repair_scale,
                                                const InitialPointTolerance& tolerance, int max_iterations = 50);

struct InvolvedValue {
  std::string name;  ///< "x'", "lambda1"
  double value = 0;
};

struct InconsistentInitialPoint {
  std::string model;       ///< "chetaev"
  std::string constraint;  ///< "hidden constraint f1", "monitored constraint f1"
  double residual = 0;
  double t0 = 0;
  InitialPointTolerance tolerance;
  std::vector<InvolvedValue> given;  ///< the given values the constraint involves
  std::vector<std::string> free;     ///< the values that may be changed and that it involves
  ConstraintSolveStatus status = ConstraintSolveStatus::independent_of_free;
};

/// "the initial values of the chetaev model violate hidden constraint f1 at t0 = 0: residual 2.5e-11
/// (tolerance 1.3e-08 = atol + …); it involves the given values x' = 1, y' = 0.5 and z' = 0.55;
/// no value that may be changed enters it. Give consistent values, or let --repair-initial
/// move the given ones to the nearest consistent point"
std::string describe(const InconsistentInitialPoint& failure);

}  // namespace nhc::base
