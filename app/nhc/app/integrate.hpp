#pragma once
/// \file integrate.hpp
/// \brief A run as its request asks for it: IDA, or the variational integrator
/// (docs/variational.md) with the request's step; the run engine's (run_engine.hpp) choice for
/// the --integrator of every front end.

#include <optional>
#include <vector>

#include "nhc/app/run_request.hpp"
#include "nhc/runtime/runtime.hpp"

namespace nhc::app {

struct IntegratedRun {
  runtime::RunResult run;
  std::optional<double> max_discrete_constraint;  ///< the variational integrator's largest residual
};

/// Integrates `model` from `initial` through `times`: with IDA (`options`, locating `events`), or,
/// when `request.variational`, with the variational integrator at `request.step` within
/// `request.max_steps` (it locates no events; check_run_request has refused --stop-when with it).
/// `model` is the one built for the integrator (jit::BuildOptions::variational).
IntegratedRun integrate(const RunRequest& request, const runtime::Model& model, const std::vector<double>& p,
                        const runtime::InitialState& initial, const std::vector<double>& times,
                        const runtime::IntegratorOptions& options, const std::vector<runtime::Event>& events,
                        const runtime::InputFunction& inputs);

}  // namespace nhc::app
