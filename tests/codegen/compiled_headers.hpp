#pragma once
// The generated headers compiled into nhc_tests_codegen (see CMakeLists.txt), each reachable
// through its model_table().
#include <vector>

#include "nhc/runtime/model_table.h"

namespace nhc_test {

struct CompiledHeader {
  const char* scene;       ///< the scene's name
  const char* scene_file;  ///< relative to the source directory
  const char* model;
  const char* jacobian;  ///< "dense" or "sparse"
  const char* path;      ///< the header in the build tree
  const nhc_model_table* (*table)();
};

const std::vector<CompiledHeader>& compiled_headers();

}  // namespace nhc_test
