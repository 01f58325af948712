#pragma once
/// \file trajectory_plots.hpp
/// \brief The pictures of one run (`nhc simulate --plot DIR`): the coordinates against t, the
/// path in a plane of two coordinates, the multipliers, and the drift of the hidden constraints
/// and invariants on a log scale, beside the run's CSV and an index plots.md.

#include <string>
#include <utility>
#include <vector>

#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"
#include "plots.hpp"

namespace nhc::cli {

/// The two coordinates spanning the plane of the path plot.
struct PathPlane {
  std::string x, y;
};

/// `--plot-xy a,b` (two different coordinate names of the scene), or with `text` empty the first
/// two coordinates. InputError naming `flag` when the names are not coordinates. A scene with one
/// coordinate has no plane: {x, ""} (no path plot).
PathPlane path_plane(const Scene& scene, const std::string& text, const std::string& flag);

/// The path plot of `models` (legend entry, CSV file) in the plane.
Plot path_plot(const std::string& stem, const std::string& title, const PathPlane& plane,
               const std::vector<std::pair<std::string, std::string>>& models);

/// Writes `directory` atomically (nhc/io/atomic_directory.hpp; an existing one is replaced only
/// when it holds plots.md): `<scene>_<model>.csv` (runtime::write_csv of the samples, the same
/// text as `simulate -o`), the plots (SVG, PNG, gnuplot script) and plots.md, which also says
/// how far the run got and why it stopped early, if it did. Returns the names of the pictures.
std::vector<std::string> write_trajectory_plots(const std::string& directory, const Scene& scene,
                                                const runtime::Model& model, const std::vector<double>& p,
                                                const runtime::RunResult& run, const PathPlane& plane,
                                                const std::vector<std::string>& inputs);

}  // namespace nhc::cli
