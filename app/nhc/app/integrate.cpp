#include "nhc/app/integrate.hpp"

namespace nhc::app {

IntegratedRun integrate(const RunRequest& request, const runtime::Model& model, const std::vector<double>& p,
                        const runtime::InitialState& initial, const std::vector<double>& times,
                        const runtime::IntegratorOptions& options, const std::vector<runtime::Event>& events,
                        const runtime::InputFunction& inputs) {
  IntegratedRun out;
  if (!request.variational) {
    out.run = runtime::simulate(model, p, initial, times, options, events, inputs);
    return out;
  }
  const runtime::VariationalOptions vo =
      runtime::variational_options(*request.step, static_cast<long>(request.max_steps), options);
  runtime::VariationalRun run = runtime::simulate_variational(model, p, initial, times, vo, inputs);
  out.run = std::move(run.run);
  out.max_discrete_constraint = run.max_discrete_constraint;
  return out;
}

}  // namespace nhc::app
