// nhc simulate --sensitivity (sensitivity_option.hpp).
#include "sensitivity_option.hpp"

#include <sstream>
#include <stdexcept>

#include "nhc/errors.hpp"
#include "nhc/base/number_text.hpp"

namespace nhc::cli {

void add_sensitivity_options(CLI::App* sub, SensitivityRequest& request) {
  sub->add_option("--sensitivity", request.names,
                  "forward sensitivities (IDAS) with respect to parameters and initial values, e.g. g,alpha,x'(0): "
                  "adds the CSV columns d(<state>)/d(<name>)")
      ->delimiter(',');
  sub->add_option("--sensitivity-error-control", request.error_control,
                  "include the sensitivities in the local error test (default on)")
      ->check(CLI::IsMember({"on", "off"}));
}

void check_sensitivities_given(const std::vector<runtime::SensitivityParameter>& thetas,
                               const runtime::InitialState& initial) {
  try {
    runtime::require_given(thetas, initial);
  } catch (const std::invalid_argument& e) {
    throw InputError({"--sensitivity", 0, 0}, e.what());
  }
}

std::string describe_sensitivity_cost(const runtime::SensitivityRun& run, const SensitivityRequest& request,
                                      const runtime::Statistics& plain) {
  const runtime::Statistics& st = run.statistics.state;
  const double seconds = st.initialization_seconds + st.integration_seconds;
  const double plain_seconds = plain.initialization_seconds + plain.integration_seconds;
  std::ostringstream os;
  os << "  sensitivities (" << request.names.size() << ", IDAS staggered, error control " << request.error_control
     << "): integrate " << base::number_text(seconds, 3)
     << " s = " << base::number_text(plain_seconds > 0 ? seconds / plain_seconds : 0, 3) << " x the plain run; steps "
     << st.steps << " (plain " << plain.steps << "), sensitivity residual evaluations "
     << run.statistics.sensitivity_residual_evaluations << "\n";
  return os.str();
}

}  // namespace nhc::cli
