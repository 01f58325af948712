#pragma once
/// \file operating_point.hpp
/// \brief Overrides of the operating point: `NAME=VALUE` with NAME a parameter or an initial
/// value written as in a scene (`th`, `ph'`, `x''`, `lambda1`; the jet form `x_d2` too).

#include <string>
#include <vector>

#include "nhc/scene/scene.hpp"

namespace nhc {

/// One `--at NAME=VALUE`.
struct PointOverride {
  std::string name;
  double value = 0.0;
};

/// What an override name stands for in a scene.
struct OverrideTarget {
  bool parameter = false;
  int parameter_index = -1;  ///< when parameter
  std::string variable;      ///< coordinate or multiplier name, when not a parameter
  int order = 0;             ///< derivative order of the variable
};

/// Parses "NAME=VALUE". Throws InputError (flag `flag`) when there is no '=' or VALUE is not
/// a finite number.
PointOverride parse_point_override(const std::string& text, const std::string& flag = "--at");

/// Resolves an override name. Throws InputError (flag `flag`) naming the scene when NAME is not
/// a parameter, coordinate or multiplier of it, or its order exceeds kMaxDerivativeOrder.
OverrideTarget resolve_override(const Scene& scene, const std::string& name, const std::string& flag = "--at");

/// Sets the value in the scene: the parameter, or the entry of the variable's [initial] list
/// (lower orders missing from the list are taken as 0 and count as given).
void apply_override(Scene& scene, const OverrideTarget& target, double value);

}  // namespace nhc
