#include "nhc/runtime/model.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <vector>

#include "nhc/base/errors.hpp"

namespace nhc::runtime {

namespace {

void validate(const nhc_model_table* t, const std::string& origin) {
  auto fail = [&](const std::string& what) {
    throw base::ModelError("model table of " + origin + ": " + what + " (see docs/generated-code.md)");
  };
  if (!t) fail("null table");
  if (t->abi_version < 1 || t->abi_version > 6)
    fail("unsupported ABI version " + std::to_string(t->abi_version) + " (this runtime reads 1 to 6)");
  if (t->n_states <= 0) fail("no states");
  if (!t->residual) fail("no residual function");
  if (!t->state_names || !t->state_variable || !t->state_order || !t->differential_id) fail("missing state metadata");
  if (t->n_parameters > 0 && (!t->default_parameters || !t->parameter_names)) fail("missing parameters");
  if (t->n_hidden > 0 && (!t->hidden_constraints || !t->hidden_constraints_jacobian))
    fail("hidden constraints declared but their functions are missing");
  if (t->n_invariants > 0 && !t->invariants) fail("invariants declared but no invariants function");
  if (t->n_reference > 0 && (!t->reference || !t->reference_coordinate))
    fail("reference declared but no reference function");
  if (t->jacobian_values && (t->jacobian_nnz <= 0 || !t->jacobian_colptr || !t->jacobian_rowind))
    fail("sparse Jacobian without its pattern");
  if (t->abi_version >= 2 && t->n_singular > 0 && !t->singular_quantities)
    fail("singular-set monitors declared but no function");
  if (t->abi_version >= 3 && t->hidden_parameter_jacobian && !t->residual_parameter_jacobian)
    fail("dg/dp without dF/dp");
  if (t->abi_version >= 4 && t->n_inputs < 0) fail("negative number of inputs");
  if (t->abi_version >= 4 && t->n_inputs > 0 && (!t->input_names || !t->default_inputs))
    fail("inputs declared but their names or default signals are missing");
  if (t->abi_version >= 5 && t->variational_residual &&
      (!t->momentum || !t->variational_jacobian || !t->variational_momentum))
    fail("a variational step without its Jacobian or momenta");
  if (t->abi_version >= 6 && t->n_speeds > 0 &&
      (!t->speed_coordinate || !t->velocities || !t->mass_matrix || !t->forcing))
    fail("independent speeds declared but their functions are missing");
}

}  // namespace

Model::Model(const nhc_model_table* table, std::shared_ptr<const void> library)
    : table_(table), library_(std::move(library)) {}

Model Model::from_table(const nhc_model_table* table) {
  validate(table, "the program");
  return Model(table, nullptr);
}

Model Model::from_table(const nhc_model_table* table, std::shared_ptr<const void> owner) {
  validate(table, table ? std::string("the interpreted model of ") + table->scene_name : std::string("the program"));
  return Model(table, std::move(owner));
}

Model Model::load(const std::string& shared_object) {
  dlerror();
  void* handle = dlopen(shared_object.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* why = dlerror();
    throw base::ModelError("cannot load " + shared_object + ": " + (why ? why : "unknown reason"));
  }
  std::shared_ptr<void> library(handle, [](void* h) { dlclose(h); });
  using Getter = const nhc_model_table* (*)();
  auto get = reinterpret_cast<Getter>(dlsym(handle, "nhc_model_table_get"));
  if (!get)
    throw base::ModelError(shared_object +
                           " has no nhc_model_table_get (was it compiled with NHC_EXPORT_MODEL_TABLE?)");
  const nhc_model_table* table = get();
  validate(table, shared_object);
  return Model(table, std::move(library));
}

bool Model::has_parameter_jacobian() const noexcept {
  return table_->n_parameters == 0 || (table_->abi_version >= 3 && table_->residual_parameter_jacobian != nullptr &&
                                       (table_->n_hidden == 0 || table_->hidden_parameter_jacobian != nullptr));
}

bool Model::has_variational_step() const noexcept {
  return table_->abi_version >= 5 && table_->variational_residual != nullptr;
}

int Model::n_speeds() const noexcept { return table_->abi_version >= 6 && table_->mass_matrix ? table_->n_speeds : 0; }

int Model::speed_coordinate(int k) const noexcept { return table_->speed_coordinate[k]; }

int Model::n_singular() const noexcept {
  return table_->abi_version >= 2 && table_->singular_quantities ? table_->n_singular : 0;
}

bool Model::has_sparse_jacobian() const noexcept {
  return table_->jacobian_values && table_->jacobian_nnz > 0 && table_->jacobian_colptr && table_->jacobian_rowind;
}

bool Model::dense_jacobian(double t, const double* y, const double* yp, double cj, const double* p, double* J) const {
  const nhc_model_table& tab = *table_;
  const int n = n_states();
  if (!tab.jacobian && !has_sparse_jacobian()) return false;
  std::fill(J, J + static_cast<long>(n) * n, 0.0);
  if (tab.jacobian) {
    tab.jacobian(t, y, yp, cj, p, J);
    return true;
  }
  std::vector<double> values(static_cast<std::size_t>(tab.jacobian_nnz));
  tab.jacobian_values(t, y, yp, cj, p, values.data());
  for (int j = 0; j < n; ++j)
    for (int k = tab.jacobian_colptr[j]; k < tab.jacobian_colptr[j + 1]; ++k)
      J[tab.jacobian_rowind[k] + static_cast<long>(n) * j] = values[static_cast<std::size_t>(k)];
  return true;
}

std::string Model::variable_name(int variable) const {
  int i = state_index(variable, 0);
  if (i >= 0) return table_->state_names[i];
  return variable < n_coordinates() ? "q" + std::to_string(variable + 1)
                                    : "lambda" + std::to_string(variable - n_coordinates() + 1);
}

int Model::state_index(int variable, int order) const noexcept {
  for (int i = 0; i < n_states(); ++i)
    if (table_->state_variable[i] == variable && table_->state_order[i] == order) return i;
  return -1;
}

std::string Model::residual_name(int i) const {
  if (table_->abi_version >= 2 && table_->residual_names && table_->residual_names[i]) return table_->residual_names[i];
  return "residual " + std::to_string(i);
}

std::string Model::hidden_name(int i) const {
  if (table_->hidden_names && table_->hidden_names[i]) return table_->hidden_names[i];
  return "hidden constraint " + std::to_string(i + 1);
}

std::string Model::singular_name(int i) const {
  if (table_->abi_version >= 2 && table_->singular_names && table_->singular_names[i]) return table_->singular_names[i];
  return "singular-set monitor " + std::to_string(i + 1);
}

std::optional<EulerAnglesMonitor> Model::euler_angles(int i) const {
  // "Euler angles psi, th, ph (z-x-z), singular at th = 0, pi"
  static const std::string prefix = "Euler angles ", at = "), singular at ";
  const std::string name = singular_name(i);
  if (name.compare(0, prefix.size(), prefix) != 0) return std::nullopt;
  const std::size_t open = name.find(" (", prefix.size()), close = name.find(at, open);
  if (open == std::string::npos || close == std::string::npos) return std::nullopt;
  const std::size_t equals = name.find(" = ", close + at.size());
  if (equals == std::string::npos) return std::nullopt;
  EulerAnglesMonitor m;
  for (std::size_t from = prefix.size();;) {
    const std::size_t comma = name.find(", ", from);
    if (comma == std::string::npos || comma > open) {
      m.angles.push_back(name.substr(from, open - from));
      break;
    }
    m.angles.push_back(name.substr(from, comma - from));
    from = comma + 2;
  }
  if (m.angles.size() != 3 || name.substr(close + at.size(), equals - close - at.size()) != m.angles[1])
    return std::nullopt;
  m.axes = name.substr(open + 2, close - open - 2);
  m.zeros = name.substr(equals + 3);
  for (int k = 0; k < n_states(); ++k)
    if (table_->state_order[k] == 0 && m.angles[1] == table_->state_names[k]) m.state = k;
  return m;
}

std::vector<double> Model::default_parameters() const {
  return std::vector<double>(table_->default_parameters, table_->default_parameters + n_parameters());
}

int Model::n_inputs() const noexcept { return table_->abi_version >= 4 ? table_->n_inputs : 0; }

std::string Model::input_name(int k) const { return table_->input_names[k]; }

int Model::input_index(const std::string& name) const noexcept {
  for (int k = 0; k < n_inputs(); ++k)
    if (name == table_->input_names[k]) return k;
  return -1;
}

int Model::parameter_index(const std::string& name) const noexcept {
  for (int i = 0; i < n_parameters(); ++i)
    if (name == table_->parameter_names[i]) return i;
  return -1;
}

}  // namespace nhc::runtime
