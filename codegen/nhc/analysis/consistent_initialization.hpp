#pragma once
/// \file consistent_initialization.hpp
/// \brief Consistent initial values for a model (models.md, "Structural analysis", step 5):
/// the x_j^(k), k < d_j, the user gave are kept; the other needed ones are solved from the
/// hidden constraints D^r f_i = 0, r < c_i; then the leading derivatives x_j^(d_j) are solved
/// from D^{c_i} f_i = 0, whose Jacobian with respect to them is the system Jacobian
/// (Pryce 2001, §4; Nedialkov & Pryce, BIT 47 (2007), consistent point of the Σ-method).
///
/// One consistent initialization in nhc: the constraints are solved by the runtime's solver
/// (nhc/base/constraint_solver.hpp, minimum-norm damped Gauss–Newton over the values not
/// given, with its tolerance), here on GiNaC-evaluated constraints and in the runtime on the
/// generated ones, so `nhc analyze` and `nhc simulate` start from the same point. The runtime's
/// is the one kept because an integration must work from a generated header alone (no GiNaC);
/// the analysis evaluates the same constraints symbolically so it needs no compiler. The
/// leading derivatives solve a square system with a nonsingular Jacobian (the system Jacobian),
/// whose solution is unique: here Newton's method, in the runtime IDACalcIC; they agree to the
/// integrator's tolerance.
///
/// A given value that violates a hidden constraint is an error naming the constraint and its
/// residual, unless repair is asked for: then every value is free and the same solver finds the
/// minimum-norm correction (the nearest consistent point to first order).

#include <ginac/ginac.h>

#include <string>
#include <vector>

#include "nhc/analysis/structural_analysis.hpp"
#include "nhc/errors.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc {

struct InitializationOptions {
  bool repair = false;
  int max_iterations = 50;
};

enum class ValueSource {
  given,      ///< from [initial], kept
  solved,     ///< solved from the hidden constraints
  repaired,   ///< given, changed by repair to satisfy the hidden constraints
  defaulted,  ///< needed, not given, not fixed by any hidden constraint: 0
  computed,   ///< a leading derivative x_j^(d_j), solved from the differentiated equations
};
std::string to_string(ValueSource source);

struct InitialValue {
  int unknown = 0;
  int order = 0;
  std::string name;  ///< "x'", "lambda1"
  double value = 0.0;
  ValueSource source = ValueSource::given;
  double given = 0.0;  ///< the value the user gave (given and repaired values)
};

struct ConsistentPoint {
  double t0 = 0.0;
  /// x_j^(k), k < d_j, in StructuralAnalysis::initial_values_needed order.
  std::vector<InitialValue> values;
  /// x_j^(d_j) for every unknown j; valid when leading_solved.
  std::vector<InitialValue> leading;
  /// False when the system Jacobian was singular before Newton converged: `leading` then holds
  /// the starting guesses, at which the caller can examine the Jacobian.
  bool leading_solved = false;
  /// The constraints imposed on the initial values: the hidden constraints, then (suslov) the
  /// monitored constraints f^α that involve initial data only; and their residuals at the point.
  std::vector<std::string> constraint_names;
  std::vector<double> constraint_residuals;
  std::vector<std::string> notes;
  /// t, the parameters and every x_j^(k), k ≤ d_j, at their values.
  GiNaC::exmap point;
};

/// A constraint the initial values must satisfy: a hidden constraint D^r f_i, r < c_i, or
/// (suslov) a monitored constraint f^α that involves initial data only.
struct InitialValueConstraint {
  GiNaC::ex expression;
  std::string name;
  bool monitored = false;
  int constraint = -1;  ///< the scene's constraint (0-based) it comes from
};
/// The constraints on the initial values, hidden ones first; the index-1 form carries the same
/// list as its hidden constraints g(t, y). Notes why a monitored constraint is left out.
std::vector<InitialValueConstraint> initial_value_constraints(const StructuralAnalysis& analysis,
                                                              std::vector<std::string>* notes = nullptr);

/// Given initial values that violate a hidden constraint, with repair not asked for: the
/// caller may offer repair (`nhc analyze --repair-initial`).
class InconsistentInitialValues : public MathError {
 public:
  using MathError::MathError;
};

/// Throws InconsistentInitialValues when the given values violate a hidden constraint and
/// repair is off; MathError when the hidden constraints cannot be satisfied (naming the constraint
/// and its residual) or Newton's method fails on the leading derivatives.
ConsistentPoint consistent_initial_point(const Scene& scene, const StructuralAnalysis& analysis,
                                         const InitializationOptions& options = {});

}  // namespace nhc
