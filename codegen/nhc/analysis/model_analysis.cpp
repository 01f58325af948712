#include "nhc/expr/work_stage.hpp"
#include "nhc/analysis/model_analysis.hpp"

#include <sstream>

#include "nhc/analysis/numeric_evaluation.hpp"
#include "nhc/analysis/system_jacobian.hpp"
#include "nhc/errors.hpp"

namespace nhc {

namespace {

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
      out.errors.push_back(describe_singular_jacobian(a, *out.jacobian, scene.initial.t0));
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
