#pragma once
/// \file pipeline.hpp
/// \brief What the commands integrating a scene share (nhc simulate, nhc report) beyond
/// nhc::jit: the scene's [initial] as the runtime's initial state, timing and number format.

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>

#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::app {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start);

// shell_quote() and run_command(): nhc/io/shell.hpp.

/// The scene's [initial] as the runtime's InitialState: `x = [x0, x'0]` gives the states x and x';
/// values beyond the states' orders are y' guesses.
runtime::InitialState initial_state_of(const Scene& scene, const runtime::Model& model);

/// A number with `precision` significant digits (iostream default notation).
std::string format_number(double v, int precision = 3);

}  // namespace nhc::app
