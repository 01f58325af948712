#pragma once
/// \file model_layout.hpp
/// \brief The data of a model's table besides its functions (docs/generated-code.md): the state
/// layout and the names. The header printer prints it; the interpreted model
/// (nhc/jit/interpreted_model.hpp) fills its table from it, so both say the same.

#include <string>
#include <vector>

#include "nhc/analysis/index1_system.hpp"
#include "nhc/emit/model_preparation.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc {

struct ModelLayout {
  std::vector<std::string> state_names;
  std::vector<int> state_variable;  ///< 0..n_coordinates-1: coordinates, then multipliers
  std::vector<int> state_order;
  std::vector<double> differential_id;  ///< IDA id: 1.0 differential, 0.0 algebraic
  std::vector<std::string> residual_names;
  std::vector<double> default_parameters;  ///< of PreparedModel::parameters, in its order
  std::vector<std::string> hidden_names;
  std::vector<std::string> invariant_names;
  std::vector<int> reference_coordinate;
  std::vector<std::string> singular_names;
  std::vector<int> speed_coordinate;  ///< Reduced-form additions: u[k] = q'[speed_coordinate[k]]
};

ModelLayout model_layout(const Scene& scene, const Index1System& system, const PreparedModel& model);

}  // namespace nhc
