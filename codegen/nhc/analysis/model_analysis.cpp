#include "nhc/expr/work_stage.hpp"
#include "nhc/analysis/model_analysis.hpp"

#include <cmath>
#include <optional>
#include <sstream>

#include "nhc/base/number_text.hpp"

#include "nhc/analysis/numeric_evaluation.hpp"
#include "nhc/analysis/system_jacobian.hpp"
#include "nhc/errors.hpp"

namespace nhc {

namespace {

/// Words for a singular system Jacobian at a point where the scene's Euler angles are singular
/// (value.hpp, docs/quaternions.md), or "": the angle, its value and the way out.
std::string euler_angles_at(const Scene& scene, const GiNaC::exmap& point) {
  for (const EulerChain& chain : scene.euler_chains) {
    const std::optional<double> determinant = finite_value(chain.determinant, point);
    if (!determinant || !(std::abs(*determinant) < 0.1)) continue;  // the runtime's kEulerAnglesNear
    const std::optional<int> angle = scene.jet->coordinate_index(chain.angles[1]);
    const std::optional<double> value = angle ? finite_value(scene.jet->q(*angle, 0), point) : std::nullopt;
    std::ostringstream s;
    s << "; the " << chain.axes << " Euler angles " << chain.angles[0] << ", " << chain.angles[1] << ", "
      << chain.angles[2] << " are singular there";
    if (value) s << " (" << chain.angles[1] << " = " << base::number_text(*value, 6) << ")";
    s << ", at " << chain.angles[1] << " = " << chain.zeros
      << ", where the angular velocity does not determine the rates: write the attitude with quat(q0, q1, q2, q3) "
         "and the constraint q0^2 + q1^2 + q2^2 + q3^2 = 1 instead (docs/quaternions.md)";
    return s.str();
  }
  return "";
}

ModelAnalysis analyze_derived_model(const Scene& scene, const DerivedModel& model,
                                    const InitializationOptions& options) {
  ModelAnalysis out;
  out.model = model.kind;
  if (!model.applicable) {
    out.applicable = false;
    out.errors.push_back("the " + to_string(model.kind) + " model is not applicable to scene '" + scene.name +
                         "': " + model.reason);
    return out;
  }
  out.structure = analyze_structure(dae_system_of(scene, model));
  const StructuralAnalysis& a = *out.structure;
  if (a.structurally_singular) {
    out.errors.push_back(a.singular_reason);
    return out;
  }
  try {
    out.initial = consistent_initial_point(scene, a, options);
    out.jacobian = evaluate_system_jacobian(system_jacobian_entries(a), a.system.size(), out.initial->point,
                                            "the system Jacobian at t0");
    const ConditionNumber condition = condition_number(*out.jacobian);
    out.jacobian_condition = condition.value;
    out.jacobian_condition_estimated = condition.estimated;
    if (!(out.jacobian_condition < kSingularCondition)) {
      out.errors.push_back(describe_singular_jacobian(a, *out.jacobian, scene.initial.t0) +
                           euler_angles_at(scene, out.initial->point));
    }
  } catch (const InconsistentInitialValues& e) {
    out.errors.push_back(e.what());
    out.initial_values_repairable = true;
  } catch (const MathError& e) {
    out.errors.push_back(e.what());
  }
  return out;
}

}  // namespace

ModelAnalysis analyze_model(const Scene& scene, const DerivedModel& model, const InitializationOptions& options) {
  const work_budget::Stage stage("analysing the model");
  return refusing_at(scene.file_location(), "analysing the " + to_string(model.kind) + " model",
                     [&] { return analyze_derived_model(scene, model, options); });
}

}  // namespace nhc
