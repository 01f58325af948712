#include "nhc/app/model_requirements.hpp"

#include "nhc/errors.hpp"

namespace nhc::app {

std::string missing_model_input(const Scene& scene, ModelKind kind) {
  if (kind != ModelKind::suslov || scene.constraints.empty()) return "";
  if (scene.dependent.size() == scene.constraints.size()) return "";
  return "the suslov model needs one dependent coordinate per constraint (key 'dependent'): the scene has " +
         std::to_string(scene.constraints.size()) + " constraint" + (scene.constraints.size() == 1 ? "" : "s") +
         " and " + std::to_string(scene.dependent.size()) + " dependent coordinate" +
         (scene.dependent.size() == 1 ? "" : "s");
}

void refuse_inputs(const Scene& scene, const std::string& what, const std::string& flag) {
  if (scene.inputs.empty()) return;
  throw InputError(scene.inputs.front().where, what + " of a scene with [inputs] (" + scene.inputs.front().name +
                                                   (scene.inputs.size() > 1 ? ", …" : "") + ") are not supported (" +
                                                   flag +
                                                   "): the generated dF/dp treats the inputs as independent "
                                                   "of the parameters (docs/runtime.md, \"Inputs\")");
}

bool scene_lists_model(const Scene& scene, ModelKind kind) { return scene.models_where.count(kind) > 0; }

void require_model_inputs(const Scene& scene, ModelKind kind) {
  const std::string missing = missing_model_input(scene, kind);
  if (missing.empty()) return;
  // The model's entry in `models`, else the `constraints` key, else the file's start.
  SourceLocation where{scene.source_path, 1, 1};
  if (const auto listed = scene.models_where.find(kind); listed != scene.models_where.end()) where = listed->second;
  else if (scene.constraints_where.line > 0) where = scene.constraints_where;
  throw InputError(where, missing);
}

}  // namespace nhc::app
