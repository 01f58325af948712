#pragma once
/// \file model_analysis.hpp
/// \brief Everything `nhc analyze` reports about one model of a scene: the Σ-method
/// (structural_analysis.hpp), the consistent initial point (consistent_initialization.hpp) and
/// the system Jacobian there with its condition number (system_jacobian.hpp). Failures are
/// collected as sentences, not thrown, so that the structure can still be shown.

#include <Eigen/Sparse>

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "nhc/analysis/consistent_initialization.hpp"
#include "nhc/analysis/structural_analysis.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc {

struct ModelAnalysis {
  ModelKind model = ModelKind::vakonomic;
  bool applicable = true;
  std::optional<StructuralAnalysis> structure;
  std::optional<ConsistentPoint> initial;
  /// System Jacobian at the consistent initial point (rows equations, columns unknowns).
  std::optional<Eigen::SparseMatrix<double>> jacobian;
  /// κ₂ of the Jacobian, or above kExactConditionLimit unknowns a 1-norm estimate of κ₁
  /// (jacobian_condition_estimated; numeric_evaluation.hpp).
  double jacobian_condition = std::numeric_limits<double>::quiet_NaN();
  bool jacobian_condition_estimated = false;
  /// Why the model cannot be integrated from the scene's initial data, in words: not
  /// applicable, structurally singular, inconsistent initial values, singular Jacobian at t0.
  std::vector<std::string> errors;

  /// The given initial values violate a hidden constraint; repair (InitializationOptions)
  /// would move them to the nearest consistent point.
  bool initial_values_repairable = false;
  bool ok() const { return errors.empty(); }
};

ModelAnalysis analyze_model(const Scene& scene, const DerivedModel& model, const InitializationOptions& options = {});

}  // namespace nhc
