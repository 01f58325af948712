#pragma once
/// \file path_functions.hpp
/// \brief The functions of a path the transcription evaluates at every collocation point, with
/// their exact first derivatives: the objective's integrand, the scene's constraints and the
/// final cost, as functions of (t, q, v) with v = q' (docs/optimize.md, "Transcription").

#include <memory>
#include <string>
#include <vector>

#include "nhc/analysis/numeric_program.hpp"
#include "nhc/optimize/settings.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::optimize {

/// A function's value and gradient at one point: d/dt, then d/dq_i, then d/dv_i.
struct ValueGradient {
  double value = 0;
  double dt = 0;
  std::vector<double> dq, dv;
};

class PathFunctions {
 public:
  /// Lowers the settings' objective and final cost and the scene's constraints, with their
  /// symbolic partial derivatives, into one NumericProgram. InputError at the expression when
  /// one holds a derivative above the first (of a coordinate) or a multiplier: the transcription
  /// takes q as states and q' as controls (docs/optimize.md, "Scope").
  PathFunctions(const Scene& scene, const Settings& settings);

  int coordinates() const noexcept { return n_; }
  int constraints() const noexcept { return m_; }
  const std::string& constraint_text(int alpha) const { return constraint_texts_[static_cast<std::size_t>(alpha)]; }

  /// Evaluates everything at (t, q, v): integrand, constraints, final cost.
  void evaluate(double t, const double* q, const double* v);
  const ValueGradient& integrand() const { return values_[0]; }
  const ValueGradient& constraint(int alpha) const { return values_[static_cast<std::size_t>(1 + alpha)]; }
  const ValueGradient& final_cost() const { return values_[static_cast<std::size_t>(1 + m_)]; }

 private:
  int n_ = 0, m_ = 0;
  std::vector<std::string> constraint_texts_;
  std::unique_ptr<NumericProgram> program_;
  std::vector<ValueGradient> values_;
  std::vector<double> inputs_;
};

}  // namespace nhc::optimize
