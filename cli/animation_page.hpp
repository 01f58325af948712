#pragma once
/// \file animation_page.hpp
/// \brief The self-contained page of `nhc animate` (docs/animate.md): DIR/index.html with the
/// shapes' samples inside it, and three.js (Debian libjs-three) copied beside it. Written
/// atomically: all of it or nothing.

#include <string>
#include <vector>

#include "visual_samples.hpp"

namespace nhc::cli {

struct AnimationContent {
  std::string scene_name, model_name;
  std::vector<double> times;
  std::vector<VisualTrack> tracks;
};

/// The page's text: cli/animation/index.html with the content as JSON in it.
std::string animation_page(const AnimationContent& content);

/// Writes `directory`/index.html, three.min.js and OrbitControls.js. `inputs` are files the
/// directory must not replace (the scene). EnvironmentError (exit 4) where libjs-three is missing.
void write_animation_page(const std::string& directory, const AnimationContent& content,
                          const std::vector<std::string>& inputs);

/// The template (cli/animation/index.html, compiled in).
const char* animation_page_template();

}  // namespace nhc::cli
