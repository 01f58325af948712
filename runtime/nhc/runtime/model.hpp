#pragma once
/// \file model.hpp
/// \brief A model the runtime can integrate: the table of docs/generated-code.md, either compiled
/// into the application (from a generated namespace, no dlopen) or loaded from a shared object.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "nhc/runtime/model_table.h"

namespace nhc::runtime {

/// A cheap-to-copy handle on a generated model. Copies share the loaded library (if any),
/// which is closed with the last copy.
/// A singular-set monitor of Euler angles, read from its name `Euler angles psi, th, ph (z-x-z),
/// singular at th = 0, pi` (docs/generated-code.md, "Runtime additions"): it is sin or cos of the
/// middle angle, zero where the angular velocity does not determine the angle rates.
struct EulerAnglesMonitor {
  std::vector<std::string> angles;  ///< the three, in the chain's order
  std::string axes;                 ///< "z-x-z"
  std::string zeros;                ///< of the middle angle: "0, pi"
  int state = -1;                   ///< the state of the middle angle, -1 when none is
};

class Model {
 public:
  /// A table compiled into this program, e.g. `Model::from_table(nhc_gen::appell_hamel_chetaev::model_table())`
  /// or, with NHC_EXPORT_MODEL_TABLE defined before the include, `Model::from_table(nhc_model_table_get())`.
  /// Throws ModelError when the table violates the contract.
  static Model from_table(const nhc_model_table* table);
  /// A table whose storage and functions `owner` keeps alive (an interpreted model,
  /// nhc/jit/interpreted_model.hpp): the model holds `owner` as it holds a loaded library.
  static Model from_table(const nhc_model_table* table, std::shared_ptr<const void> owner);

  /// dlopen()s a shared object built from a generated header with NHC_EXPORT_MODEL_TABLE and
  /// takes its table. Throws ModelError with dlerror()'s message on failure.
  static Model load(const std::string& shared_object);

  const nhc_model_table& table() const noexcept { return *table_; }
  int abi_version() const noexcept { return table_->abi_version; }
  std::string scene_name() const { return table_->scene_name; }
  std::string model_name() const { return table_->model_name; }
  int n_states() const noexcept { return table_->n_states; }
  int n_parameters() const noexcept { return table_->n_parameters; }
  int n_coordinates() const noexcept { return table_->n_coordinates; }
  int n_multipliers() const noexcept { return table_->n_multipliers; }
  int n_hidden() const noexcept { return table_->n_hidden; }
  int n_invariants() const noexcept { return table_->n_invariants; }
  int n_reference() const noexcept { return table_->n_reference; }
  /// Singular-set monitors (Runtime additions, abi_version >= 2), else 0.
  int n_singular() const noexcept;

  /// dF/dp generated (Sensitivity additions, abi_version >= 3; always true without parameters).
  bool has_parameter_jacobian() const noexcept;

  /// The discrete Lagrange–d'Alembert step generated (Variational additions, abi_version >= 5):
  /// what `simulate_variational` (variational.hpp) integrates with.
  bool has_variational_step() const noexcept;

  /// The independent speeds of the multiplier-free form M_r u' = f_r (Reduced-form additions,
  /// abi_version >= 6, docs/reduced-form.md), else 0: then mass_matrix, forcing and velocities
  /// of the table are null.
  int n_speeds() const noexcept;
  /// The coordinate whose first derivative is independent speed k (0 <= k < n_speeds()).
  int speed_coordinate(int k) const noexcept;

  bool has_dense_jacobian() const noexcept { return table_->jacobian != nullptr; }
  bool has_sparse_jacobian() const noexcept;
  /// J = dF/dy + cj dF/dy' at (t, y, y') with the parameters and inputs `p`, column-major n×n:
  /// the generated dense Jacobian, or the sparse one scattered (the one sparse-to-dense scatter).
  /// False, with J untouched, when the model carries neither.
  bool dense_jacobian(double t, const double* y, const double* yp, double cj, const double* p, double* J) const;

  std::string state_name(int i) const { return table_->state_names[i]; }
  bool is_differential(int i) const noexcept { return table_->differential_id[i] != 0.0; }
  /// Name of unknown j (coordinate, then multiplier): the state name of order 0.
  std::string variable_name(int variable) const;
  /// State index holding the order-th derivative of unknown `variable`, or -1.
  int state_index(int variable, int order) const noexcept;
  /// "R_x" from the generated names when available (abi >= 2), else "residual 3".
  std::string residual_name(int i) const;
  std::string hidden_name(int i) const;
  std::string singular_name(int i) const;
  /// Monitor i as Euler angles, or nullopt for a monitor of the equations' own singular set
  /// (which a run stops at).
  std::optional<EulerAnglesMonitor> euler_angles(int i) const;
  std::vector<double> default_parameters() const;
  int parameter_index(const std::string& name) const noexcept;
  /// The scene's inputs (Input additions, abi_version >= 4; else 0): the generated functions read
  /// input k at p[n_parameters() + k] (nhc/runtime/inputs.hpp sets them during a run).
  int n_inputs() const noexcept;
  std::string input_name(int k) const;
  int input_index(const std::string& name) const noexcept;  ///< -1 when no input has the name

 private:
  Model(const nhc_model_table* table, std::shared_ptr<const void> library);
  const nhc_model_table* table_ = nullptr;
  std::shared_ptr<const void> library_;
};

}  // namespace nhc::runtime

/// The model of a generated namespace compiled into this program, e.g.
/// `auto model = NHC_RUNTIME_MODEL(nhc_gen::appell_hamel_chetaev);`
#define NHC_RUNTIME_MODEL(generated_namespace) ::nhc::runtime::Model::from_table(generated_namespace::model_table())
