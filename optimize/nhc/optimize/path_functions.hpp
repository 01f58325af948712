#pragma once
/// \file path_functions.hpp
/// \brief The functions of a PointProblem evaluated at one collocation point with their exact
/// sparse first derivatives: each function's partial derivatives by t and by the slots it
/// depends on (through named intermediates), all lowered once into one NumericProgram
/// (docs/optimize.md, "Derivatives").

#include <memory>
#include <utility>
#include <vector>

#include "nhc/expr/numeric_program.hpp"
#include "nhc/optimize/point_problem.hpp"

namespace nhc::optimize {

/// A function's value and its derivatives at one point: by t, and by the slots of its
/// structure (PathFunctions::slots), in that order.
struct ValueGradient {
  double value = 0;
  double dt = 0;
  std::vector<double> d;
  /// Second derivatives over the pairs of PathFunctions::pairs (after evaluate_second()).
  std::vector<double> dd;
};

/// A pair of a function's variables for a second derivative: -1 is t, k >= 0 the slot k; first >= second.
using VariablePair = std::pair<int, int>;

class PathFunctions {
 public:
  /// Functions in this order: the integrand, the final cost, the path rows, the initial rows.
  explicit PathFunctions(const PointProblem& problem);

  int functions() const noexcept { return static_cast<int>(slots_.size()); }
  /// The slots function f depends on, increasing.
  const std::vector<int>& slots(int f) const { return slots_[static_cast<std::size_t>(f)]; }

  /// The pairs of t and slots whose second derivative of function f is not identically 0.
  const std::vector<VariablePair>& pairs(int f) const { return pairs_[static_cast<std::size_t>(f)]; }

  /// Evaluates every function at t and the point's slots (y, y', u).
  void evaluate(double t, const double* point);
  /// Evaluates every function's value only (ValueGradient::value; the derivatives keep their
  /// old values): what the constraint and objective values need, and all that IPOPT's finite
  /// differences ask for.
  void evaluate_values(double t, const double* point);
  /// Evaluates every function's second derivatives there (into ValueGradient::dd).
  void evaluate_second(double t, const double* point);
  const ValueGradient& value(int f) const { return values_[static_cast<std::size_t>(f)]; }

 private:
  void set_inputs(double t, const double* point);

  std::vector<std::vector<int>> slots_;
  std::vector<std::vector<VariablePair>> pairs_;
  std::unique_ptr<NumericProgram> program_, values_only_, second_;
  std::vector<ValueGradient> values_;
  std::vector<double> inputs_;
  int slot_count_ = 0;
};

}  // namespace nhc::optimize
