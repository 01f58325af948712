#include "nhc/jit/interpreted_model.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "nhc/emit/model_layout.hpp"
#include "nhc/emit/model_table_text.hpp"
#include "nhc/errors.hpp"
#include "nhc/expr/evaluation_program.hpp"

namespace nhc::jit {

namespace {

// The table's function fields the interpreter fills, by name (docs/generated-code.md).
#define NHC_INTERPRETED_FIELDS(X)                                                                                 \
  X(residual) X(jacobian) X(jacobian_values) X(hidden_constraints) X(hidden_constraints_jacobian) X(invariants) \
  X(reference) X(singular_quantities) X(residual_parameter_jacobian) X(hidden_parameter_jacobian)               \
  X(default_inputs) X(momentum) X(variational_residual) X(variational_jacobian) X(variational_momentum)          \
  X(velocities) X(mass_matrix) X(forcing)

enum Field : int {
#define NHC_FIELD_ENUM(name) field_##name,
  NHC_INTERPRETED_FIELDS(NHC_FIELD_ENUM)
#undef NHC_FIELD_ENUM
  kFieldCount
};

int field_of(const std::string& function) {
#define NHC_FIELD_NAME(name) \
  if (function == #name) return field_##name;
  NHC_INTERPRETED_FIELDS(NHC_FIELD_NAME)
#undef NHC_FIELD_NAME
  return -1;
}

struct InterpretedFunction {
  bool present = false;
  EvaluationProgram program;
  int zero_fill = 0;  ///< FunctionPlan::zero_fill
};

class Interpreter;
std::array<std::atomic<const Interpreter*>, kInterpretedModelSlots> g_slots{};
std::atomic<std::uint64_t> g_generation{0};

/// One thread's registers of one function of one slot, valid for the interpreter of `generation`.
struct Registers {
  std::uint64_t generation = 0;
  std::vector<double> values;
};
thread_local std::array<std::array<Registers, kFieldCount>, kInterpretedModelSlots> t_registers;

class Interpreter {
 public:
  Interpreter(const Scene& scene, const Index1System& system, const PreparedModel& m);
  Interpreter(const Interpreter&) = delete;
  Interpreter& operator=(const Interpreter&) = delete;
  ~Interpreter() {
    if (slot_ >= 0) g_slots[static_cast<std::size_t>(slot_)].store(nullptr, std::memory_order_release);
  }

  /// Evaluates function `field`: arguments[0 .. count-2] are its inputs in the order of its
  /// signature, arguments[count-1] its output array.
  void call(int field, const double* const* arguments, std::size_t count) const noexcept {
    const InterpretedFunction& f = functions_[static_cast<std::size_t>(field)];
    double* out = const_cast<double*>(arguments[count - 1]);
    if (f.zero_fill > 0) std::fill(out, out + f.zero_fill, 0.0);
    Registers& registers = t_registers[static_cast<std::size_t>(slot_)][static_cast<std::size_t>(field)];
    if (registers.generation != generation_) {
      registers.generation = generation_;
      registers.values.clear();
    }
    double* outputs[] = {out};
    f.program.run(arguments, outputs, registers.values);
  }

  const nhc_model_table* table() const noexcept { return &table_; }
  /// adopt_compiled(): the compiled functions in place of the entry points.
  bool adopt(const runtime::Model& compiled);
  /// Takes a free slot and enters its entry points into the table.
  void install();

 private:
  std::array<InterpretedFunction, kFieldCount> functions_;
  std::uint64_t generation_ = ++g_generation;
  int slot_ = -1;
  std::string scene_name_, model_name_;
  ModelLayout layout_;
  std::vector<std::string> parameter_names_, input_names_;
  std::vector<const char*> state_names_, residual_names_, parameter_pointers_, input_pointers_, hidden_names_,
      invariant_names_, singular_names_;
  std::vector<int> colptr_, rowind_;
  nhc_model_table table_{};
  std::vector<runtime::Model> adopted_;  ///< keeps the compiled library loaded
};

const double* address(const double& value) { return &value; }
const double* address(const double* values) { return values; }

/// The entry point of field F in slot S: the table's C signature, forwarded to the interpreter.
template <int S, int F, typename... A>
void entry_point(A... a) noexcept {
  const double* arguments[] = {address(a)...};
  g_slots[S].load(std::memory_order_acquire)->call(F, arguments, sizeof...(A));
}
template <int S, int F, typename... A>
auto entry_point_like(void (*)(A...)) -> void (*)(A...) {
  return &entry_point<S, F, A...>;
}

template <int S>
void install_in_slot(nhc_model_table& t, const std::array<InterpretedFunction, kFieldCount>& functions) {
#define NHC_FIELD_INSTALL(name) \
  if (functions[field_##name].present) t.name = entry_point_like<S, field_##name>(t.name);
  NHC_INTERPRETED_FIELDS(NHC_FIELD_INSTALL)
#undef NHC_FIELD_INSTALL
}
template <std::size_t... S>
void install_in(int slot, nhc_model_table& t, const std::array<InterpretedFunction, kFieldCount>& functions,
                std::index_sequence<S...>) {
  ((slot == static_cast<int>(S) ? install_in_slot<static_cast<int>(S)>(t, functions) : void()), ...);
}

/// "y[3]" → ("y", 3); "t" → ("t", 0).
std::pair<std::string, int> split_name(const std::string& name) {
  const std::size_t bracket = name.find('[');
  if (bracket == std::string::npos) return {name, 0};
  return {name.substr(0, bracket), std::stoi(name.substr(bracket + 1))};
}

InterpretedFunction interpreted_function(const FunctionPlan& f, const ExpressionDag& dag) {
  std::vector<std::string> inputs;  // the signature's names but the output's, in order
  for (const auto& [type, name] : f.parameters)
    if (type != "double*") inputs.push_back(name);
  std::vector<EvaluationProgram::Output> outputs;
  for (const Assignment& a : f.assignments) outputs.push_back({a.value, 0, split_name(a.target).second});
  InterpretedFunction interpreted;
  interpreted.present = true;
  interpreted.zero_fill = f.zero_fill;
  interpreted.program = EvaluationProgram(dag, outputs, [&](const Instruction& in) {
    const auto [array, index] = split_name(in.name);
    const auto at = std::find(inputs.begin(), inputs.end(), array);
    if (at == inputs.end())
      throw MathError(f.name + " depends on " + in.name + ", which it does not receive");
    return EvaluationProgram::InputLocation{static_cast<int>(at - inputs.begin()), index};
  });
  return interpreted;
}

std::vector<const char*> pointers(const std::vector<std::string>& names) {
  std::vector<const char*> p;
  for (const std::string& name : names) p.push_back(name.c_str());
  return p;
}

Interpreter::Interpreter(const Scene& scene, const Index1System& system, const PreparedModel& m)
    : scene_name_(scene.name),
      model_name_(m.model),
      layout_(model_layout(scene, system, m)),
      parameter_names_(m.parameter_names),
      input_names_(m.input_names) {
  for (const FunctionPlan& f : m.functions) {
    const int field = field_of(f.name);
    if (field < 0) throw MathError("the interpreter has no entry for the generated function " + f.name);
    functions_[static_cast<std::size_t>(field)] = interpreted_function(f, m.dag);
  }
  state_names_ = pointers(layout_.state_names);
  residual_names_ = pointers(layout_.residual_names);
  parameter_pointers_ = pointers(parameter_names_);
  input_pointers_ = pointers(input_names_);
  hidden_names_ = pointers(layout_.hidden_names);
  invariant_names_ = pointers(layout_.invariant_names);
  singular_names_ = pointers(layout_.singular_names);
  nhc_model_table& t = table_;
  t.abi_version = kModelTableAbiVersion;
  t.scene_name = scene_name_.c_str();
  t.model_name = model_name_.c_str();
  t.n_states = m.n_states;
  t.n_parameters = m.n_parameters;
  t.n_coordinates = m.n_coordinates;
  t.n_multipliers = m.n_multipliers;
  t.n_hidden = m.n_hidden;
  t.n_invariants = m.n_invariants;
  t.n_reference = m.n_reference;
  t.state_names = state_names_.data();
  t.state_variable = layout_.state_variable.data();
  t.state_order = layout_.state_order.data();
  t.differential_id = layout_.differential_id.data();
  if (m.n_parameters > 0) {
    t.parameter_names = parameter_pointers_.data();
    t.default_parameters = layout_.default_parameters.data();
  }
  if (m.n_hidden > 0) t.hidden_names = hidden_names_.data();
  if (m.n_invariants > 0) t.invariant_names = invariant_names_.data();
  if (m.n_reference > 0) t.reference_coordinate = layout_.reference_coordinate.data();
  if (functions_[field_jacobian_values].present) {
    colptr_ = m.symbolic_jacobian.colptr;
    rowind_ = m.symbolic_jacobian.rowind;
    if (rowind_.empty()) rowind_.push_back(0);  // as the header's placeholder
    t.jacobian_nnz = static_cast<int>(m.symbolic_jacobian.rowind.size());
    t.jacobian_colptr = colptr_.data();
    t.jacobian_rowind = rowind_.data();
  }
  t.residual_names = residual_names_.data();
  t.n_singular = m.n_singular;
  if (m.n_singular > 0) t.singular_names = singular_names_.data();
  t.n_inputs = m.n_inputs;
  if (m.n_inputs > 0) t.input_names = input_pointers_.data();
  t.n_speeds = m.n_speeds;
  if (m.n_speeds > 0) t.speed_coordinate = layout_.speed_coordinate.data();
}

void Interpreter::install() {
  for (int s = 0; s < kInterpretedModelSlots; ++s) {
    const Interpreter* expected = nullptr;
    if (g_slots[static_cast<std::size_t>(s)].compare_exchange_strong(expected, this, std::memory_order_acq_rel)) {
      slot_ = s;
      install_in(s, table_, functions_, std::make_index_sequence<kInterpretedModelSlots>{});
      return;
    }
  }
  throw EnvironmentError(std::to_string(kInterpretedModelSlots) +
                         " interpreted models exist already in this process: release one, or compile (--backend compiled)");
}

bool Interpreter::adopt(const runtime::Model& compiled) {
  const nhc_model_table& c = compiled.table();
  if (c.n_states != table_.n_states || c.n_parameters != table_.n_parameters || c.n_inputs != table_.n_inputs ||
      c.n_hidden != table_.n_hidden || c.jacobian_nnz != table_.jacobian_nnz)
    return false;
  adopted_.push_back(compiled);
#define NHC_FIELD_ADOPT(name) \
  if (table_.name) table_.name = c.name;
  NHC_INTERPRETED_FIELDS(NHC_FIELD_ADOPT)
#undef NHC_FIELD_ADOPT
  return true;
}

}  // namespace

bool adopt_compiled(const runtime::Model& interpreted, const runtime::Model& compiled) {
  for (const auto& slot : g_slots) {
    const Interpreter* interpreter = slot.load(std::memory_order_acquire);
    if (interpreter && interpreter->table() == &interpreted.table())
      return const_cast<Interpreter*>(interpreter)->adopt(compiled);
  }
  return false;
}

bool interpretable(const PreparedModel& model) {
  return std::all_of(model.functions.begin(), model.functions.end(),
                     [](const FunctionPlan& f) { return field_of(f.name) >= 0; });
}

runtime::Model interpret(const Scene& scene, const Index1System& system, const PreparedModel& model) {
  auto interpreter = std::make_shared<Interpreter>(scene, system, model);
  interpreter->install();
  const nhc_model_table* table = interpreter->table();
  return runtime::Model::from_table(table, std::shared_ptr<const void>(interpreter, table));
}

}  // namespace nhc::jit
