#pragma once
/// \file settings.hpp
/// \brief A scene's [optimize] table (docs/scenes.md, "Optimal motions"; docs/optimize.md): the objective,
/// the horizon, the boundary conditions and the bounds of `nhc optimize`.

#include <ginac/ginac.h>

#include <optional>
#include <string>
#include <vector>

#include "nhc/errors.hpp"
#include "nhc/scene/model_kind.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::optimize {

/// A coordinate's derivative, an input or an [outputs] quantity by its scene name (nhc/scene/scene.hpp).
using nhc::PathQuantity;

/// `x = 0.0` of [optimize.initial] or [optimize.final], or `x = [low, high]` (a bound there).
struct BoundaryValue {
  PathQuantity quantity;
  double low = 0, high = 0;
  SourceLocation where;
};

/// `u1 = [-5.0, 5.0]` of [optimize.bounds]: low <= quantity <= high along the whole path.
struct PathBound {
  PathQuantity quantity;
  double low = 0, high = 0;
  SourceLocation where;
};

struct Settings {
  GiNaC::ex objective;  ///< the integrand; default the Lagrangian
  SourceLocation objective_where;
  GiNaC::ex final_cost = 0;  ///< of t and the final state
  SourceLocation final_cost_where;
  double t_end_low = 1, t_end_high = 1;  ///< equal: a fixed horizon
  SourceLocation t_end_where;
  int intervals = 40;
  std::optional<ModelKind> model;  ///< used when the scene has [inputs]
  SourceLocation model_where;      ///< the `model` entry (else the table's header)
  std::vector<BoundaryValue> initial, final;
  std::vector<PathBound> bounds;
  SourceLocation table_where;  ///< the [optimize] header

  bool free_time() const { return t_end_low != t_end_high; }
};

/// The scene's [optimize] (read with the scene, Scene::optimize) at the scene's parameter values.
/// Every problem is an InputError at its FILE:LINE:COLUMN; a scene without the table is one too
/// (at the file).
Settings read_settings(const Scene& scene);

}  // namespace nhc::optimize
