#pragma once
/// \file scene_visual.hpp
/// \brief [visual]: named shapes attached to the scene's own quantities, for `nhc animate`
/// (docs/animate.md). Positions are 3-vectors and orientations 3×3 rotation matrices in the
/// scene's fixed frame (z up), written as expressions of t, parameters, coordinates (with
/// derivatives) and definitions; they are evaluated on the samples of a run.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "nhc/errors.hpp"
#include "nhc/scene/value.hpp"

namespace nhc {

enum class VisualShape { sphere, cylinder, box, segment, trace, plane };

/// What a key of a shape holds.
enum class VisualValueKind {
  scalar,    ///< a length: radius, length; a number or an expression
  vector,    ///< a point or a size: a 3-vector expression, or an array of three numbers/expressions
  rotation,  ///< body to space, a 3×3 rotation matrix
};

struct VisualKey {
  const char* name;
  VisualValueKind kind;
  bool required;
};

/// The shape's keys that hold quantities (the policy of which shape takes what, in one place):
///   sphere   radius, center, [rotation]        drawn in coloured octants, so that spin shows
///   cylinder radius, length, center, [rotation] (and axis = "x" | "y" | "z", default "z")
///   box      size (3 edge lengths), center, [rotation]
///   segment  from, to
///   trace    point                             the path the point draws
///   plane    [size]                            the ground z = 0 (size: its side, default: fitted)
/// Every shape also takes color ("#rrggbb" or "#rgb") and opacity (0 … 1).
const std::vector<VisualKey>& visual_keys(VisualShape shape);

std::optional<VisualShape> parse_visual_shape(const std::string& name);
const char* to_string(VisualShape shape);
/// "sphere, cylinder, box, segment, trace, plane"
std::string visual_shape_names();

struct SceneVisual {
  std::string name;
  VisualShape shape = VisualShape::sphere;
  SourceLocation where;                 ///< the entry in the scene file
  std::map<std::string, Value> values;  ///< by key of visual_keys(shape): a scalar, a 3-vector or a 3×3 rotation
  std::map<std::string, SourceLocation> value_where;  ///< where each value is written
  int axis = 2;                                       ///< a cylinder's axis in its own frame: 0 x, 1 y, 2 z
  std::string color;                                  ///< "#rrggbb", "" for the page's choice
  double opacity = 1.0;
};

}  // namespace nhc
