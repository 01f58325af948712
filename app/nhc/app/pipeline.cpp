// The shared pipeline of the integrating commands (pipeline.hpp).
#include "nhc/app/pipeline.hpp"

#include "nhc/runtime/number_text.hpp"

#include <sstream>

namespace nhc::app {

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

runtime::InitialState initial_state_of(const Scene& scene, const runtime::Model& model) {
  return runtime::initial_state_from(model, scene.initial.t0, scene.initial.values);
}

std::string format_number(double v, int precision) { return runtime::number_text(v, precision); }

}  // namespace nhc::app
