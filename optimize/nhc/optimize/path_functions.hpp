#pragma once
/// \file path_functions.hpp
/// \brief The functions of a PointProblem evaluated at one collocation point with their exact
/// sparse first derivatives: each function's partial derivatives by t and by the slots it
/// depends on (through named intermediates), all lowered once into one NumericProgram
/// (docs/optimize.md, "Derivatives").

#include <memory>
#include <vector>

#include "nhc/analysis/numeric_program.hpp"
#include "nhc/optimize/point_problem.hpp"

namespace nhc::optimize {

/// A function's value and its derivatives at one point: by t, and by the slots of its
/// structure (PathFunctions::slots), in that order.
struct ValueGradient {
  double value = 0;
  double dt = 0;
  std::vector<double> d;
};

class PathFunctions {
 public:
  /// Functions in this order: the integrand, the final cost, the path rows, the initial rows.
  explicit PathFunctions(const PointProblem& problem);

  int functions() const noexcept { return static_cast<int>(slots_.size()); }
  /// The slots function f depends on, increasing.
  const std::vector<int>& slots(int f) const { return slots_[static_cast<std::size_t>(f)]; }

  /// Evaluates every function at t and the point's slots (y, y', u).
  void evaluate(double t, const double* point);
  const ValueGradient& value(int f) const { return values_[static_cast<std::size_t>(f)]; }

 private:
  std::vector<std::vector<int>> slots_;
  std::unique_ptr<NumericProgram> program_;
  std::vector<ValueGradient> values_;
  std::vector<double> inputs_;
  int slot_count_ = 0;
};

}  // namespace nhc::optimize
