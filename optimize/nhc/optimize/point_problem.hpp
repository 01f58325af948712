#pragma once
/// \file point_problem.hpp
/// \brief What the transcription needs at one collocation point, as expressions: the states y,
/// their rates y' and the inputs u that each point holds, the objective's integrand and final
/// cost, the rows that hold at every point (the scene's constraints, or the model's index-1
/// residual F(t, y, y', u) = 0; bounds on named quantities), the rows that hold at the first point
/// (the hidden constraints), and the bounds and boundary values on single variables
/// (docs/optimize.md, "Two problems from one table").

#include <ginac/ginac.h>

#include <string>
#include <vector>

#include "nhc/errors.hpp"
#include "nhc/optimize/settings.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::optimize {

/// low <= expression <= high (equal: an equation), `name` in words for the messages.
struct PointRow {
  GiNaC::ex expression;
  std::string name;
  double low = 0, high = 0;
};

/// A variable of a point by its slot: y_k (k < states), y'_k (states + k), u_k (2 states + k).
struct SlotBound {
  int slot = 0;
  double low = 0, high = 0;
  std::string name;
  SourceLocation where;
};

struct PointProblem {
  bool dynamics = false;  ///< the scene's [inputs] drive the model's DAE (else the vakonomic problem)
  ModelKind model = ModelKind::vakonomic;
  int states = 0, inputs = 0;
  std::vector<std::string> state_names, input_names;  ///< "x", "x'", "lambda1"; "u1"
  /// Per state: collocated (its y' is its rate) or algebraic (a multiplier without derivative in
  /// F: its y' is held at 0 and no collocation row is written for it).
  std::vector<bool> collocated;
  /// The symbols the expressions hold, in this order: t, y, y', u, then the parameters (whose
  /// values are `parameter_values`).
  std::vector<GiNaC::ex> symbols;
  std::vector<double> parameter_values;
  GiNaC::ex integrand, final_cost;
  std::vector<PointRow> path;  ///< at every point
  /// With [inputs]: the first `dynamics_rows` rows of `path` are the model's residual F (as many
  /// as states); the others bound named quantities.
  int dynamics_rows = 0;
  std::vector<PointRow> initial_rows;  ///< at the first point only
  std::vector<SlotBound> bounds;
  std::vector<SlotBound> initial, final;  ///< at the first and the last point (low = high: a value)
  /// The values of `initial` are a state measured by a run, set by HermiteSimpson::restart before
  /// each solve (model predictive control, docs/mpc.md): not checked against the bounds, and the
  /// hidden constraints they decide are the run's to keep (its drift), not rows of the problem.
  bool measured_start = false;

  int slots() const { return 2 * states + inputs; }
};

/// Without [inputs]: y = q, y' = q' and the scene's constraints at every point.
PointProblem vakonomic_problem(const Scene& scene, const Settings& settings);
/// With [inputs]: the index-1 form of `model` (reduce_to_index1), its residual at every point and
/// its hidden constraints at the first. MathError when the model does not apply.
PointProblem dynamics_problem(const Scene& scene, const Settings& settings, ModelKind model);
/// The one the scene asks for: dynamics_problem with [inputs] (the settings' model, default
/// chetaev), else vakonomic_problem.
PointProblem point_problem(const Scene& scene, const Settings& settings);

}  // namespace nhc::optimize
