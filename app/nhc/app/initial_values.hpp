#pragma once
/// \file initial_values.hpp
/// \brief Initial values given from outside the scene (the command line's `--initial NAME=VALUE`,
/// Python's `initial=` and `t0=`): each replaces, or adds, one entry of the scene's [initial] as
/// if it had been written there, so the consistent-initialization rules apply unchanged.

#include <string>
#include <vector>

#include "nhc/runtime/integrator.hpp"
#include "nhc/runtime/model.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::app {

/// One value: `name` is t0, or a coordinate or multiplier with as many primes as the
/// derivative's order ("x", "x'", "lambda1"); `written` is the assignment as the caller gave it,
/// for messages, which are located at the caller's field and quote it ("--initial: error: x=nan:
/// …"); empty when the field alone names the value (Python's t0=).
struct InitialValue {
  std::string name;
  double value = 0;
  std::string written;
};

/// The scene with `values` written into its [initial] (the last of repeated names wins). A name
/// that is neither t0, a coordinate nor a multiplier, a derivative order beyond the scene's
/// limit, a value that is not finite, or a derivative whose lower orders neither the scene nor
/// `values` give ("x'" without x) is an InputError at `field`. A value written over an [initial]
/// expression of the parameters replaces it (a later --set does not re-evaluate it). A new t0
/// moves the default end of the run, t0 + 1, with it when [simulate] gives no t_end.
void apply_initial_values(Scene& scene, const std::vector<InitialValue>& values, const std::string& field);

/// The scene's [initial] as the runtime's InitialState: `x = [x0, x'0]` gives the states x and x';
/// values beyond the states' orders are y' guesses.
runtime::InitialState initial_state_of(const Scene& scene, const runtime::Model& model);

}  // namespace nhc::app
