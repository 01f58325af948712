#pragma once
/// \file scene_reader.hpp
/// \brief What the parts of the scene reader (scene_loader.cpp and the readers of its tables)
/// share; not installed: the public face is load_scene() and parse_scene() (scene.hpp).

#include "nhc/scene/scene_toml.hpp"

#include <string>

#include "nhc/scene/scene.hpp"

namespace nhc::scene_reading {

/// Non-printable bytes are shown as \xNN so that the one-line message stays one line; a
/// long text is cut after 60 bytes (at a character boundary) and marked with "...".
std::string printable(const std::string& text);

/// [optimize] of the scene file's table `root` into scene.optimize, once the rest of the scene is
/// read (its names, parameters, [simulate] and [outputs]). Every problem is an InputError at its
/// FILE:LINE:COLUMN of `path`.
void read_optimize(const toml::table& root, Scene& scene, const std::string& path);

}  // namespace nhc::scene_reading
