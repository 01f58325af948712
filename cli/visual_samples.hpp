#pragma once
/// \file visual_samples.hpp
/// \brief The scene's [visual] shapes evaluated along a run: each shape's point(s) and rotation
/// at every sample, its sizes at the first one (what `nhc animate` puts in its page).

#include <string>
#include <vector>

#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::cli {

struct VisualTrack {
  const SceneVisual* visual = nullptr;
  std::vector<double> position;  ///< 3 per sample: center, point, or a segment's `from`
  std::vector<double> to;        ///< 3 per sample: a segment's `to`
  std::vector<double> rotation;  ///< 9 per sample (row-major, body to space); empty: none given
  double radius = 0, length = 0;
  std::vector<double> size;  ///< a box's three edges; a plane's side (one entry, when given)
};

/// Every visual of `scene` on `samples`. A visual using a quantity the model does not compute
/// (a multiplier of the suslov model) is an InputError at its entry; a value that is not a
/// finite number at t0 (a radius sqrt(-1)) is an InputError at its key.
std::vector<VisualTrack> visual_tracks(const Scene& scene, const runtime::Model& model, const std::vector<double>& p,
                                       const std::vector<runtime::Sample>& samples);

}  // namespace nhc::cli
