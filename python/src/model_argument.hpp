#pragma once
/// \file model_argument.hpp
/// \brief A model named by a Python argument ("chetaev"), or nhc.SceneError naming the known ones.

#include <optional>
#include <string>

#include "nhc/errors.hpp"
#include "nhc/scene/model_kind.hpp"

namespace nhc::python {

inline ModelKind model_named(const std::string& name) {
  const std::optional<ModelKind> kind = parse_model_kind(name);
  if (!kind) throw InputError({"model", 0, 0}, "unknown model '" + name + "' (known: " + model_name_list() + ")");
  return *kind;
}

}  // namespace nhc::python
