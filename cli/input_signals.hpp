#pragma once
/// \file input_signals.hpp
/// \brief The `--input` signals, from their home in app/ (nhc/app/input_signals.hpp).

#include "nhc/app/input_signals.hpp"

namespace nhc::cli {

using app::input_files;
using app::input_function;
using app::InputSignals;
using app::parse_input_signals;

}  // namespace nhc::cli
