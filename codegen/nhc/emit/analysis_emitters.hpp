#pragma once
/// \file analysis_emitters.hpp
/// \brief Writing model analyses (Σ-method, consistent initial point, system Jacobian) for
/// people (text) and tools (JSON). Implementations: analysis_text_emitter.cpp,
/// analysis_json_emitter.cpp.

#include <ostream>
#include <vector>

#include "nhc/analysis/model_analysis.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc {

/// Per model: σ as a table, transversal, offsets, index, dof, needed initial values, hidden
/// constraints, the consistent initial point, the Jacobian condition number, notes, errors.
void write_analysis_text(std::ostream& out, const Scene& scene, const std::vector<ModelAnalysis>& analyses);

/// One object per model: {"model", "unknowns", "equations", "sigma" (null for −∞), "c", "d",
/// "index", "dof", "initial_values_needed", "hidden_constraints", "jacobian_condition",
/// "jacobian_condition_estimated" (true: a 1-norm estimate, docs/analysis.md),
/// "initial_values", "notes", "errors"}; a single object when there is one analysis, else an
/// array of them.
void write_analysis_json(std::ostream& out, const Scene& scene, const std::vector<ModelAnalysis>& analyses);

}  // namespace nhc
