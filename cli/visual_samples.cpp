#include "visual_samples.hpp"

#include <cmath>

#include "nhc/app/sample_expressions.hpp"

namespace nhc::cli {

namespace {

/// The slots of one visual's values in a SampleExpressions.
struct Slots {
  std::string key;
  std::size_t first = 0, count = 0;
};

}  // namespace

std::vector<VisualTrack> visual_tracks(const Scene& scene, const runtime::Model& model, const std::vector<double>& p,
                                       const std::vector<runtime::Sample>& samples) {
  app::SampleExpressions expressions(scene, model, p);
  std::vector<std::vector<Slots>> slots(scene.visuals.size());
  for (std::size_t v = 0; v < scene.visuals.size(); ++v) {
    const SceneVisual& visual = scene.visuals[v];
    for (const auto& [key, value] : visual.values) {
      Slots s{key, expressions.size(), value.entries.size()};
      for (const GiNaC::ex& e : value.entries)
        if (const std::string missing = expressions.add(e); !missing.empty())
          throw InputError(visual.value_where.at(key), "visual '" + visual.name + "' " + key + " uses " + missing +
                                                           ", which the " + model.model_name() +
                                                           " model does not compute");
      slots[v].push_back(s);
    }
  }
  std::vector<VisualTrack> tracks(scene.visuals.size());
  for (std::size_t v = 0; v < tracks.size(); ++v) tracks[v].visual = &scene.visuals[v];
  for (std::size_t r = 0; r < samples.size(); ++r) {
    const std::vector<double> values = expressions.evaluate(samples[r]);
    for (std::size_t v = 0; v < tracks.size(); ++v) {
      VisualTrack& track = tracks[v];
      const SceneVisual& visual = scene.visuals[v];
      for (const Slots& s : slots[v]) {
        const auto begin = values.begin() + static_cast<std::ptrdiff_t>(s.first);
        const auto end = begin + static_cast<std::ptrdiff_t>(s.count);
        if (s.key == "center" || s.key == "point" || s.key == "from")
          track.position.insert(track.position.end(), begin, end);
        else if (s.key == "to") track.to.insert(track.to.end(), begin, end);
        else if (s.key == "rotation") track.rotation.insert(track.rotation.end(), begin, end);
        else if (r == 0) {  // sizes: at the first sample
          for (auto it = begin; it != end; ++it)
            if (!std::isfinite(*it) || *it < 0)
              throw InputError(visual.value_where.at(s.key), "visual '" + visual.name + "' " + s.key +
                                                                 " is not a finite length at t0 (" +
                                                                 std::to_string(*it) + ")");
          if (s.key == "radius") track.radius = *begin;
          else if (s.key == "length") track.length = *begin;
          else track.size.assign(begin, end);
        }
      }
    }
  }
  return tracks;
}

}  // namespace nhc::cli
