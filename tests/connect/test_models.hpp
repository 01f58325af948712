#pragma once
// Models of the example scenes for the [sensitivity] and [connect] tests, built with nhc::jit
// (with dF/dp) into a cache under the build directory.
#include <string>

#include "nhc/jit.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::test {

inline jit::LoadedModel example_model(const std::string& scene_file, ModelKind kind) {
  jit::BuildOptions options;
  options.sensitivities = true;
  options.compile.cache_directory = std::string(NHC_BINARY_DIR) + "/tests/connect/nhc-cache";
  return jit::build(load_scene(std::string(NHC_SOURCE_DIR) + "/examples/" + scene_file), kind, options);
}

}  // namespace nhc::test
