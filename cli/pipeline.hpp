#pragma once
/// \file pipeline.hpp
/// \brief What the commands integrating a scene share, from its home in app/
/// (nhc/app/pipeline.hpp).

#include "nhc/app/pipeline.hpp"

namespace nhc::cli {

using app::Clock;
using app::format_number;
using app::initial_state_of;
using app::seconds_since;

}  // namespace nhc::cli
