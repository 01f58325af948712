#pragma once
/// \file input_signals.hpp
/// \brief `nhc simulate --input NAME=EXPR` and `--input NAME=@FILE.csv` (repeatable):
/// a signal that replaces the default of one of the scene's inputs for one run.
///
/// EXPR is an expression of t and the scene's parameters (their values after --set), in the scene
/// language. FILE.csv has a header row naming a column `t` and a column NAME (others are ignored);
/// its times increase strictly and cover the run, and between them the input is interpolated
/// linearly. Bad input is exit 2 naming the flag, or FILE:LINE:COLUMN for the file's content.

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "nhc/runtime/inputs.hpp"
#include "nhc/runtime/model.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::app {

/// The --input signals, checked against the scene (its parameter values after --set are the ones
/// an EXPR reads); `t0`, `t_end`: the run a CSV must cover. Before anything is compiled.
struct InputSignals {
  using Signal = std::function<double(double t)>;
  std::vector<std::pair<int, Signal>> signals;  ///< input index (scene order), its signal
};
/// The files the --input assignments read (NAME=@FILE), which no output may replace.
std::vector<std::string> input_files(const std::vector<std::string>& assignments);

InputSignals parse_input_signals(const Scene& scene, const std::vector<std::string>& assignments, double t0,
                                 double t_end);

/// The inputs' values during a run of `model` (whose inputs are the scene's, in its order): the
/// default signals at `parameters`, the --input signals in place of theirs; empty without any.
runtime::InputFunction input_function(const InputSignals& signals, const runtime::Model& model,
                                      const std::vector<double>& parameters);

}  // namespace nhc::app
