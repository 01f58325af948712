#include "nhc/derive/reduced_form.hpp"
#include "nhc/emit/derivation_emitters.hpp"
#include "nhc/expr/intermediate.hpp"

namespace nhc {

std::vector<GiNaC::ex> derivation_intermediates(const Scene& scene, const std::vector<DerivedModel>& models) {
  std::vector<GiNaC::ex> printed = {scene.lagrangian};
  printed.insert(printed.end(), scene.constraints.begin(), scene.constraints.end());
  for (const DerivedModel& model : models) {
    if (!model.applicable) continue;
    printed.insert(printed.end(), model.equations.begin(), model.equations.end());
    printed.insert(printed.end(), model.constraints.begin(), model.constraints.end());
    if (model.reduced && model.reduced->available) {
      const std::vector<GiNaC::ex> reduced = model.reduced->expressions();
      printed.insert(printed.end(), reduced.begin(), reduced.end());
    }
  }
  return intermediates_in_order(printed);
}

}  // namespace nhc
