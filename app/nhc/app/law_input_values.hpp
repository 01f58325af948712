#pragma once
/// \file law_input_values.hpp
/// \brief The values a feedback law of the scene's [inputs] applies, written into a run's samples.
///
/// A law u(t, q, q') is compiled into the equations in place of its input's symbol (scene.hpp,
/// SceneInput::law), so the run's input array holds the input's default signal, 0, and not what
/// the law applied. The generated default_inputs reads t and the parameters only (it cannot
/// evaluate a law of the state), so the law is evaluated here on each sample, once the run is
/// made, and every writer of the samples (the CSV's `input:NAME` columns, Python's Run, animate)
/// records the law's value.

#include <vector>

#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::app {

/// Writes u_k = law_k(t, q, q') into sample.u for each feedback-law input of `scene` that `model`
/// reads, with the parameter values `p` (the model's order); NaN where the model does not compute
/// a quantity the law uses. Samples without inputs (read back from a file) are left as they are.
void record_law_inputs(const Scene& scene, const runtime::Model& model, const std::vector<double>& p,
                       std::vector<runtime::Sample>& samples);
/// The same for the samples of a run with sensitivities (the plain columns of its CSV).
void record_law_inputs(const Scene& scene, const runtime::Model& model, const std::vector<double>& p,
                       std::vector<runtime::SensitivitySample>& samples);

}  // namespace nhc::app
