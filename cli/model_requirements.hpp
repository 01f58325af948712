#pragma once
/// \file model_requirements.hpp
/// \brief The scene's requirements of a model, from their home in app/ (nhc/app/model_requirements.hpp).

#include "nhc/app/model_requirements.hpp"

namespace nhc::cli {

using app::missing_model_input;
using app::refuse_inputs;
using app::require_model_inputs;
using app::scene_lists_model;

}  // namespace nhc::cli
