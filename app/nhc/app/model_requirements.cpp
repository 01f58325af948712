#include "nhc/app/model_requirements.hpp"

#include "nhc/scene/scene_toml.hpp"

#include <optional>

#include "nhc/errors.hpp"

namespace nhc::app {

namespace {

/// The scene file's TOML (already validated by the loader), or nothing for a scene built in code.
std::optional<toml::table> scene_table(const Scene& scene) {
  if (scene.source_path.empty()) return std::nullopt;
  try {
    return toml::parse_file(scene.source_path);
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

SourceLocation location_of(const Scene& scene, const toml::node* node) {
  if (!node) return {scene.source_path, 1, 1};
  const toml::source_region& r = node->source();
  return {scene.source_path, static_cast<int>(r.begin.line), static_cast<int>(r.begin.column)};
}

/// The node of `kind` in the `models` array, or nullptr.
const toml::node* listed_model(const toml::table& root, ModelKind kind) {
  const toml::array* models = root["models"].as_array();
  if (!models) return nullptr;
  for (const toml::node& m : *models)
    if (const auto name = m.value<std::string>(); name && *name == to_string(kind)) return &m;
  return nullptr;
}

}  // namespace

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
  throw InputError(scene.inputs.front().where,
                   what + " of a scene with [inputs] (" + scene.inputs.front().name + (scene.inputs.size() > 1 ? ", …" : "") +
                       ") are not supported (" + flag + "): the generated dF/dp treats the inputs as independent "
                       "of the parameters (docs/runtime.md, \"Inputs\")");
}

bool scene_lists_model(const Scene& scene, ModelKind kind) {
  const std::optional<toml::table> root = scene_table(scene);
  return root && listed_model(*root, kind) != nullptr;
}

void require_model_inputs(const Scene& scene, ModelKind kind) {
  const std::string missing = missing_model_input(scene, kind);
  if (missing.empty()) return;
  const std::optional<toml::table> root = scene_table(scene);
  const toml::node* where = nullptr;
  if (root) {
    where = listed_model(*root, kind);
    if (!where) where = root->get("constraints");
  }
  throw InputError(location_of(scene, where), missing);
}

}  // namespace nhc::app
