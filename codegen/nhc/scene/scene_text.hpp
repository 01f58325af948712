#pragma once
/// \file scene_text.hpp
/// \brief A scene's text with [inputs] entries rewritten: a feedback law given from outside the
/// file (`--input NAME=EXPR` of the coordinates) read through the same path as one written there.

#include <map>
#include <set>
#include <string>

namespace nhc {

/// The scene text with the [inputs] entries named in `laws` written as those expressions: each
/// value replaced in place, every other line and column unchanged. `text` must be a scene
/// parse_scene() accepted; std::invalid_argument for a name it has no [inputs] entry for, or a
/// law holding a quote, backslash or line break.
std::string scene_text_with_inputs(const std::string& text, const std::map<std::string, std::string>& laws);

/// True when the scene's [simulate] gives t_end (else the scene's end is t0 + 1, which follows a
/// t0 set from outside, nhc/app/initial_values.hpp). `text` must be a scene parse_scene() accepted.
bool scene_gives_t_end(const std::string& text);

/// The names of the scene's [definitions] (empty when it has none). `text` must be a scene
/// parse_scene() accepted.
std::set<std::string> scene_definition_names(const std::string& text);

}  // namespace nhc
