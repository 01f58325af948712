// The pictures of one run: nhc simulate --plot DIR (trajectory_plots.hpp).
#include "trajectory_plots.hpp"

#include <algorithm>
#include <sstream>

#include "nhc/errors.hpp"
#include "nhc/io/atomic_directory.hpp"
#include "nhc/io/atomic_file.hpp"
#include "nhc/base/number_text.hpp"

namespace nhc::cli {

namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

std::vector<std::string> coordinate_names(const runtime::Model& model) {
  std::vector<std::string> names;
  for (int v = 0; v < model.n_coordinates(); ++v) names.push_back(model.variable_name(v));
  return names;
}

std::vector<Plot> trajectory_plots(const runtime::Model& model, const std::string& csv, const PathPlane& plane) {
  const std::string label = model.scene_name() + " (" + model.model_name() + ")";
  std::vector<Plot> plots;

  Plot coordinates{"coordinates", "coordinates against t: " + label, "t", "coordinate value", false, false, {}};
  for (const std::string& q : coordinate_names(model)) coordinates.curves.push_back({q, csv, "t", q});
  plots.push_back(coordinates);

  if (!plane.y.empty())
    plots.push_back(path_plot("path", "path in the " + plane.x + "," + plane.y + " plane: " + label, plane,
                              {{model.model_name(), csv}}));

  if (model.n_multipliers() > 0) {
    Plot multipliers{"multipliers", "multipliers against t: " + label, "t", "multiplier value", false, false, {}};
    for (int a = 0; a < model.n_multipliers(); ++a) {
      const std::string name = model.variable_name(model.n_coordinates() + a);
      multipliers.curves.push_back({name, csv, "t", name});
    }
    plots.push_back(multipliers);
  }

  if (model.n_hidden() + model.n_invariants() > 0) {
    Plot drift{"drift", "drift of the hidden constraints and invariants: " + label,
               "t",     "|g_i|  and  |I(t) - I(t0)|  (log scale)",
               true,    false,
               {}};
    for (int i = 0; i < model.n_hidden(); ++i)
      drift.curves.push_back({"|g_" + std::to_string(i + 1) + "|: " + model.hidden_name(i), csv, "t",
                              runtime::hidden_column(model, i), Transform::magnitude});
    for (int k = 0; k < model.n_invariants(); ++k) {
      const std::string name = model.table().invariant_names[k];
      drift.curves.push_back({name + ": |I(t) - I(t0)|", csv, "t", "invariant:" + name, Transform::drift});
    }
    plots.push_back(drift);
  }
  return plots;
}

}  // namespace

PathPlane path_plane(const Scene& scene, const std::string& text, const std::string& flag) {
  const std::vector<std::string>& coordinates = scene.jet->coordinates();
  if (text.empty()) return {coordinates.front(), coordinates.size() > 1 ? coordinates[1] : ""};
  const auto comma = text.find(',');
  auto bad = [&](const std::string& why) {
    throw InputError({flag, 0, 0}, "'" + text + "': " + why + " (the coordinates are " + joined(coordinates) + ")");
  };
  if (comma == std::string::npos) bad("expected two coordinate names separated by a comma, e.g. x,y");
  const PathPlane plane{text.substr(0, comma), text.substr(comma + 1)};
  for (const std::string& name : {plane.x, plane.y})
    if (std::find(coordinates.begin(), coordinates.end(), name) == coordinates.end())
      bad("'" + name + "' is not a coordinate of scene " + scene.name);
  if (plane.x == plane.y) bad("two different coordinates are needed");
  return plane;
}

Plot path_plot(const std::string& stem, const std::string& title, const PathPlane& plane,
               const std::vector<std::pair<std::string, std::string>>& models) {
  Plot path{stem, title, plane.x, plane.y, false, true, {}};
  for (const auto& [name, csv] : models) path.curves.push_back({name, csv, plane.x, plane.y});
  return path;
}

std::vector<std::string> write_trajectory_plots(const std::string& directory, const Scene& scene,
                                                const runtime::Model& model, const std::vector<double>& p,
                                                const runtime::RunResult& run, const PathPlane& plane,
                                                const std::vector<std::string>& inputs) {
  AtomicDirectory out(directory, inputs);
  const std::filesystem::path staging = out.path();
  const std::string csv = scene.name + "_" + model.model_name() + ".csv";
  runtime::write_csv((staging / csv).string(), model, p, run.samples);
  const std::vector<Plot> plots = trajectory_plots(model, csv, plane);
  draw_plots(staging, plots);

  std::ostringstream md;
  const double t_last = run.samples.back().t;
  md << "# " << scene.name << ", model " << model.model_name() << "\n\n"
     << "Drawn by `nhc simulate --plot` from [" << csv << "](" << csv << ") (" << run.samples.size()
     << " rows, the columns of `nhc simulate -o`): t from " << base::number_text(run.samples.front().t, 6) << " to "
     << base::number_text(t_last, 6) << ".";
  if (run.failure) md << " The run stopped there: " << run.failure->what();
  md << "\n\nEach picture is also a PNG of the same name, drawn by its gnuplot script (`NAME.gp`; redraw with "
        "`gnuplot NAME.gp` in this directory). On the log scale of the drift, values below "
     << base::number_text(kLogFloor, 3) << " are drawn at " << base::number_text(kLogFloor, 3) << ".\n\n"
     << markdown_images(plots);
  write_file_atomically((staging / "plots.md").string(), [&](std::ostream& o) { o << md.str(); });
  out.commit();

  std::vector<std::string> names{"plots.md", csv};
  for (const Plot& plot : plots) names.push_back(plot.stem + ".svg"), names.push_back(plot.stem + ".png");
  return names;
}

}  // namespace nhc::cli
