#include "nhc/optimize/settings.hpp"

#include "nhc/base/number_text.hpp"

namespace nhc::optimize {

namespace {

/// An entry of [optimize.initial], [optimize.final] or [optimize.bounds] at `parameters`.
void evaluate(const SceneOptimizeEntry& entry, const std::map<std::string, double>& parameters, double& low,
              double& high) {
  low = entry.low.value_at(parameters);
  high = entry.range ? entry.high.value_at(parameters) : low;
  if (entry.range && !(low <= high))
    throw InputError(entry.value_where, "the low bound of " + entry.what + " is above its high bound");
}

std::vector<BoundaryValue> boundary(const std::vector<SceneOptimizeEntry>& entries,
                                    const std::map<std::string, double>& parameters) {
  std::vector<BoundaryValue> out;
  for (const SceneOptimizeEntry& entry : entries) {
    BoundaryValue b;
    b.quantity = entry.quantity;
    b.where = entry.where;
    evaluate(entry, parameters, b.low, b.high);
    out.push_back(b);
  }
  return out;
}

}  // namespace

Settings read_settings(const Scene& scene) {
  const SceneOptimize& table = scene.optimize;
  if (!table.present)
    throw InputError(scene.file_location(), "the scene has no [optimize] table (docs/scenes.md, \"Optimal motions\")");
  // The scene's values now: a parameter set since the file was read counts.
  const std::map<std::string, double> parameters = scene.parameter_values_by_name();
  Settings s;
  s.table_where = table.where;
  s.objective = table.objective ? table.objective->subs(scene.parameter_substitution()) : scene.lagrangian;
  s.objective_where = table.objective ? table.objective_where : scene.lagrangian_where;
  s.final_cost = table.final_cost.subs(scene.parameter_substitution());
  s.final_cost_where = table.final_cost_where;
  const double t0 = scene.initial.t0;
  s.t_end_low = s.t_end_high = scene.simulate.t_end;
  s.t_end_where = table.t_end_where;
  if (table.t_end.size() == 2) {
    s.t_end_low = table.t_end[0].value_at(parameters);
    s.t_end_high = table.t_end[1].value_at(parameters);
    if (!(s.t_end_low > t0))
      throw InputError(table.t_end[0].where, "t_end's low bound must be after t0 = " + base::number_text(t0, 6));
    if (!(s.t_end_high > s.t_end_low))
      throw InputError(table.t_end[1].where, "t_end's high bound must be above its low bound");
  } else if (table.t_end.size() == 1) {
    s.t_end_low = s.t_end_high = table.t_end[0].value_at(parameters);
    if (!(s.t_end_low > t0))
      throw InputError(table.t_end[0].where, "t_end must be after t0 = " + base::number_text(t0, 6));
  }
  if (table.intervals) s.intervals = *table.intervals;
  s.model = table.model;
  s.model_where = table.model_where;
  s.initial = boundary(table.initial, parameters);
  s.final = boundary(table.final, parameters);
  for (const SceneOptimizeEntry& entry : table.bounds) {
    PathBound b;
    b.quantity = entry.quantity;
    b.where = entry.where;
    evaluate(entry, parameters, b.low, b.high);
    s.bounds.push_back(b);
  }
  return s;
}

}  // namespace nhc::optimize
