#pragma once
/// \file model_requirements.hpp
/// \brief What a model needs from a scene beyond what every model needs, checked as bad input
/// (exit 2, located in the scene file) before anything is derived: Suslov's model eliminates
/// one dependent velocity per constraint (paper eq. (29)), so it needs `dependent`.

#include <string>
#include <vector>

#include "nhc/scene/model_kind.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::app {

/// Why `kind` cannot be derived from the scene's keys, "" when it can.
std::string missing_model_input(const Scene& scene, ModelKind kind);

/// Throws InputError at the scene (the 'suslov' entry of `models`, else the `constraints` key)
/// when `kind` was asked for (by --model, or listed in the scene's `models`) and lacks its input.
void require_model_inputs(const Scene& scene, ModelKind kind);

/// Throws InputError at the scene's first input when it has [inputs] and `what` (forward
/// sensitivities, a boundary-value problem) cannot take them; `flag` names what asked for it.
void refuse_inputs(const Scene& scene, const std::string& what, const std::string& flag);

/// The models the scene lists by name in its `models` key (not the implicit default, all models).
bool scene_lists_model(const Scene& scene, ModelKind kind);

}  // namespace nhc::app
