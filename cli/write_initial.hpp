#pragma once
/// \file write_initial.hpp
/// \brief `nhc analyze --repair-initial --write-initial FILE`: the consistent initial point as a
/// scene's [initial] table (17 significant digits, so it reads back to the same doubles), with
/// the [initial] fixed list kept — to paste into the scene.

#include <iosfwd>

#include "nhc/analysis/consistent_initialization.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::cli {

void write_initial_table(std::ostream& out, const Scene& scene, const std::string& model, const ConsistentPoint& point);

}  // namespace nhc::cli
