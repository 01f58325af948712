#pragma once
/// \file input_laws.hpp
/// \brief Feedback laws given from outside the scene (`--input NAME=EXPR` of the coordinates):
/// written into the scene's [inputs] text and the scene read again, so that the law takes the
/// one path of a law written in the file (compiled into the equations, algebraic loops refused;
/// docs/scenes.md, "Feedback laws") and the scene cache keys on it.

#include <map>
#include <string>

#include "nhc/scene/scene.hpp"

namespace nhc::app {

/// True when `text`, the value given for the scene's input `name`, is an expression of the
/// coordinates (a feedback law), not a signal of t and the parameters. A law of an acceleration
/// is an InputError at `field` (an algebraic loop); text that does not parse is not a law (the
/// signal's own reading reports it).
bool is_feedback_law(const Scene& scene, const std::string& name, const std::string& text, const std::string& field);

/// The scene read again with `laws` (input name → expression) in its [inputs]; the parameter
/// values and [initial] of `scene` (set from outside before) are kept. InputError at `field`.
Scene scene_with_input_laws(const Scene& scene, const std::map<std::string, std::string>& laws,
                            const SceneOptions& options, const std::string& field);

}  // namespace nhc::app
