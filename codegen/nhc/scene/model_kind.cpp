// Model names and the default model (model_kind.hpp).
#include "nhc/scene/model_kind.hpp"

#include "nhc/scene/scene.hpp"

namespace nhc {

std::string to_string(ModelKind model) {
  switch (model) {
    case ModelKind::vakonomic:
      return "vakonomic";
    case ModelKind::chetaev:
      return "chetaev";
    case ModelKind::holder:
      return "holder";
    case ModelKind::suslov:
      return "suslov";
  }
  return "?";
}

std::optional<ModelKind> parse_model_kind(const std::string& name) {
  for (ModelKind m : kAllModels)
    if (to_string(m) == name) return m;
  return std::nullopt;
}

std::vector<std::string> model_names() {
  std::vector<std::string> names;
  for (ModelKind m : kAllModels) names.push_back(to_string(m));
  return names;
}

std::string model_name_list() {
  std::string list;
  for (const std::string& name : model_names()) list += (list.empty() ? "" : ", ") + name;
  return list;
}

ModelKind default_model(const Scene& scene) {
  if (scene.simulate.model) return *scene.simulate.model;
  for (ModelKind m : scene.models)
    if (m == ModelKind::chetaev) return m;
  return scene.models.empty() ? ModelKind::chetaev : scene.models.front();
}

ModelKind model_or_default(const Scene& scene, const std::string& name) {
  if (!name.empty())
    if (const auto kind = parse_model_kind(name)) return *kind;
  return default_model(scene);
}

}  // namespace nhc
