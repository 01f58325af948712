#include "nhc/jit/interpreted_model.hpp"

#include <algorithm>
#include <array>
#include <cstring>
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
// clang-format off
#define NHC_INTERPRETED_FIELDS(X) \
  X(residual)                     \
  X(jacobian)                     \
  X(jacobian_values)              \
  X(hidden_constraints)           \
  X(hidden_constraints_jacobian)  \
  X(invariants)                   \
  X(reference)                    \
  X(singular_quantities)          \
  X(residual_parameter_jacobian)  \
  X(hidden_parameter_jacobian)    \
  X(default_inputs)               \
  X(momentum)                     \
  X(variational_residual)         \
  X(variational_jacobian)         \
  X(variational_momentum)         \
  X(velocities)                   \
  X(mass_matrix)                  \
  X(forcing)
// clang-format on

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

/// The inputs (arguments but the output array) of a table function with this signature.
template <typename... A>
constexpr int inputs_of(void (*)(A...)) {
  return static_cast<int>(sizeof...(A)) - 1;
}
constexpr int kFieldInputs[] = {
#define NHC_FIELD_INPUTS(name) inputs_of(decltype(nhc_model_table::name){}),
    NHC_INTERPRETED_FIELDS(NHC_FIELD_INPUTS)
#undef NHC_FIELD_INPUTS
};

struct InterpretedFunction {
  bool present = false;
  EvaluationProgram program;
  int zero_fill = 0;  ///< FunctionPlan::zero_fill
};

}  // namespace

class InterpretedProgram {
 public:
  std::string scene_name, model_name;
  int n_states = 0, n_parameters = 0, n_coordinates = 0, n_multipliers = 0, n_hidden = 0, n_invariants = 0,
      n_reference = 0, n_singular = 0, n_inputs = 0, n_speeds = 0;
  ModelLayout layout;
  std::vector<std::string> parameter_names, input_names;
  std::vector<int> colptr, rowind;  ///< the sparse Jacobian's structure, when jacobian_values is present
  std::array<InterpretedFunction, kFieldCount> functions;
};

namespace {

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
  explicit Interpreter(std::shared_ptr<const InterpretedProgram> program);
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
  std::shared_ptr<const InterpretedProgram> program_;
  const std::array<InterpretedFunction, kFieldCount>& functions_;
  std::uint64_t generation_ = ++g_generation;
  int slot_ = -1;
  std::vector<const char*> state_names_, residual_names_, parameter_pointers_, input_pointers_, hidden_names_,
      invariant_names_, singular_names_;
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
    if (at == inputs.end()) throw MathError(f.name + " depends on " + in.name + ", which it does not receive");
    return EvaluationProgram::InputLocation{static_cast<int>(at - inputs.begin()), index};
  });
  return interpreted;
}

std::vector<const char*> pointers(const std::vector<std::string>& names) {
  std::vector<const char*> p;
  for (const std::string& name : names) p.push_back(name.c_str());
  return p;
}

Interpreter::Interpreter(std::shared_ptr<const InterpretedProgram> program)
    : program_(std::move(program)), functions_(program_->functions) {
  const InterpretedProgram& m = *program_;
  const ModelLayout& layout = m.layout;
  state_names_ = pointers(layout.state_names);
  residual_names_ = pointers(layout.residual_names);
  parameter_pointers_ = pointers(m.parameter_names);
  input_pointers_ = pointers(m.input_names);
  hidden_names_ = pointers(layout.hidden_names);
  invariant_names_ = pointers(layout.invariant_names);
  singular_names_ = pointers(layout.singular_names);
  nhc_model_table& t = table_;
  t.abi_version = kModelTableAbiVersion;
  t.scene_name = m.scene_name.c_str();
  t.model_name = m.model_name.c_str();
  t.n_states = m.n_states;
  t.n_parameters = m.n_parameters;
  t.n_coordinates = m.n_coordinates;
  t.n_multipliers = m.n_multipliers;
  t.n_hidden = m.n_hidden;
  t.n_invariants = m.n_invariants;
  t.n_reference = m.n_reference;
  t.state_names = state_names_.data();
  t.state_variable = layout.state_variable.data();
  t.state_order = layout.state_order.data();
  t.differential_id = layout.differential_id.data();
  if (m.n_parameters > 0) {
    t.parameter_names = parameter_pointers_.data();
    t.default_parameters = layout.default_parameters.data();
  }
  if (m.n_hidden > 0) t.hidden_names = hidden_names_.data();
  if (m.n_invariants > 0) t.invariant_names = invariant_names_.data();
  if (m.n_reference > 0) t.reference_coordinate = layout.reference_coordinate.data();
  if (functions_[field_jacobian_values].present) {
    t.jacobian_nnz = m.colptr.empty() ? 0 : m.colptr.back();
    t.jacobian_colptr = m.colptr.data();
    t.jacobian_rowind = m.rowind.data();
  }
  t.residual_names = residual_names_.data();
  t.n_singular = m.n_singular;
  if (m.n_singular > 0) t.singular_names = singular_names_.data();
  t.n_inputs = m.n_inputs;
  if (m.n_inputs > 0) t.input_names = input_pointers_.data();
  t.n_speeds = m.n_speeds;
  if (m.n_speeds > 0) t.speed_coordinate = layout.speed_coordinate.data();
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
  throw EnvironmentError(
      std::to_string(kInterpretedModelSlots) +
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

// ---------------------------------------------------------------------------------------------
// The program as bytes: little-endian 32-bit words, doubles by their 64 bits, texts and lists
// preceded by their lengths; each function's EvaluationProgram::to_bytes() as a text.

constexpr const char* kProgramMagic = "nhc interpreted program 1";

struct Writer {
  std::string out;
  void word(std::uint32_t v) {
    for (int k = 0; k < 4; ++k) out.push_back(static_cast<char>((v >> (8 * k)) & 0xffu));
  }
  void integer(int v) { word(static_cast<std::uint32_t>(v)); }
  void text(const std::string& t) {
    word(static_cast<std::uint32_t>(t.size()));
    out += t;
  }
  void integers(const std::vector<int>& v) {
    word(static_cast<std::uint32_t>(v.size()));
    for (int x : v) integer(x);
  }
  void reals(const std::vector<double>& v) {
    word(static_cast<std::uint32_t>(v.size()));
    for (double x : v) {
      std::uint64_t bits = 0;
      std::memcpy(&bits, &x, sizeof bits);
      word(static_cast<std::uint32_t>(bits));
      word(static_cast<std::uint32_t>(bits >> 32));
    }
  }
  void texts(const std::vector<std::string>& v) {
    word(static_cast<std::uint32_t>(v.size()));
    for (const std::string& t : v) text(t);
  }
};

/// Reads what Writer wrote; every read fails (and `ok` turns false) once the bytes run out.
struct Reader {
  std::string_view bytes;
  std::size_t pos = 0;
  bool ok = true;
  std::uint32_t word() {
    if (!ok || bytes.size() - pos < 4) return ok = false, 0;
    std::uint32_t v = 0;
    for (int k = 0; k < 4; ++k) v |= static_cast<std::uint32_t>(static_cast<unsigned char>(bytes[pos + k])) << (8 * k);
    pos += 4;
    return v;
  }
  int integer() { return static_cast<int>(word()); }
  /// A count of items of at least `item_bytes` each that the rest can hold.
  std::size_t count(std::size_t item_bytes) {
    const std::size_t n = word();
    if (!ok || n > (bytes.size() - pos) / item_bytes) return ok = false, 0;
    return n;
  }
  std::string_view text() {
    const std::size_t n = count(1);
    const std::string_view t = ok ? bytes.substr(pos, n) : std::string_view();
    pos += n;
    return t;
  }
  std::vector<int> integers() {
    std::vector<int> v(count(4));
    for (int& x : v) x = integer();
    return v;
  }
  std::vector<double> reals() {
    std::vector<double> v(count(8));
    for (double& x : v) {
      const std::uint64_t low = word(), high = word();
      const std::uint64_t bits = (high << 32) | low;
      std::memcpy(&x, &bits, sizeof x);
    }
    return v;
  }
  std::vector<std::string> texts() {
    std::vector<std::string> v(count(4));
    for (std::string& t : v) t = std::string(text());
    return v;
  }
};

/// Whether the data of `p` agree with its sizes: the table built from them points into
/// arrays as long as its sizes say.
bool consistent(const InterpretedProgram& p) {
  const ModelLayout& l = p.layout;
  auto size_is = [](const auto& v, int n) { return n >= 0 && v.size() == static_cast<std::size_t>(n); };
  if (!size_is(l.state_names, p.n_states) || !size_is(l.state_variable, p.n_states) ||
      !size_is(l.state_order, p.n_states) || !size_is(l.differential_id, p.n_states) ||
      !size_is(l.residual_names, p.n_states) || !size_is(l.default_parameters, p.n_parameters) ||
      !size_is(p.parameter_names, p.n_parameters) || !size_is(l.hidden_names, p.n_hidden) ||
      !size_is(l.invariant_names, p.n_invariants) || !size_is(l.reference_coordinate, p.n_reference) ||
      !size_is(l.singular_names, p.n_singular) || !size_is(p.input_names, p.n_inputs) ||
      !size_is(l.speed_coordinate, p.n_speeds) || p.n_coordinates < 0 || p.n_multipliers < 0)
    return false;
  if (!p.functions[field_residual].present) return false;
  if (p.functions[field_jacobian_values].present) {
    if (!size_is(p.colptr, p.n_states + 1) || p.colptr.front() != 0) return false;
    for (std::size_t k = 1; k < p.colptr.size(); ++k)
      if (p.colptr[k] < p.colptr[k - 1]) return false;
    const std::size_t nnz = static_cast<std::size_t>(p.colptr.back());
    if (p.rowind.size() != std::max<std::size_t>(nnz, 1)) return false;
    for (std::size_t k = 0; k < nnz; ++k)
      if (p.rowind[k] < 0 || p.rowind[k] >= p.n_states) return false;
  }
  return true;
}

}  // namespace

std::shared_ptr<const InterpretedProgram> interpreted_program(const Scene& scene, const Index1System& system,
                                                              const PreparedModel& m) {
  auto p = std::make_shared<InterpretedProgram>();
  p->scene_name = scene.name;
  p->model_name = m.model;
  p->layout = model_layout(scene, system, m);
  p->parameter_names = m.parameter_names;
  p->input_names = m.input_names;
  p->n_states = m.n_states;
  p->n_parameters = m.n_parameters;
  p->n_coordinates = m.n_coordinates;
  p->n_multipliers = m.n_multipliers;
  p->n_hidden = m.n_hidden;
  p->n_invariants = m.n_invariants;
  p->n_reference = m.n_reference;
  p->n_singular = m.n_singular;
  p->n_inputs = m.n_inputs;
  p->n_speeds = m.n_speeds;
  for (const FunctionPlan& f : m.functions) {
    const int field = field_of(f.name);
    if (field < 0) throw MathError("the interpreter has no entry for the generated function " + f.name);
    p->functions[static_cast<std::size_t>(field)] = interpreted_function(f, m.dag);
  }
  if (p->functions[field_jacobian_values].present) {
    p->colptr = m.symbolic_jacobian.colptr;
    p->rowind = m.symbolic_jacobian.rowind;
    if (p->rowind.empty()) p->rowind.push_back(0);  // as the header's placeholder
  }
  return p;
}

std::string to_bytes(const InterpretedProgram& p) {
  Writer w;
  w.text(kProgramMagic);
  w.text(p.scene_name);
  w.text(p.model_name);
  for (int n : {p.n_states, p.n_parameters, p.n_coordinates, p.n_multipliers, p.n_hidden, p.n_invariants, p.n_reference,
                p.n_singular, p.n_inputs, p.n_speeds})
    w.integer(n);
  const ModelLayout& l = p.layout;
  w.texts(l.state_names);
  w.integers(l.state_variable);
  w.integers(l.state_order);
  w.reals(l.differential_id);
  w.texts(l.residual_names);
  w.reals(l.default_parameters);
  w.texts(l.hidden_names);
  w.texts(l.invariant_names);
  w.integers(l.reference_coordinate);
  w.texts(l.singular_names);
  w.integers(l.speed_coordinate);
  w.texts(p.parameter_names);
  w.texts(p.input_names);
  w.integers(p.colptr);
  w.integers(p.rowind);
  for (const InterpretedFunction& f : p.functions) {
    w.integer(f.present ? 1 : 0);
    if (!f.present) continue;
    w.integer(f.zero_fill);
    w.text(f.program.to_bytes());
  }
  return std::move(w.out);
}

std::shared_ptr<const InterpretedProgram> interpreted_program_from_bytes(std::string_view bytes,
                                                                         const std::string& scene_name,
                                                                         const std::string& model) {
  Reader r{bytes};
  if (r.text() != kProgramMagic || !r.ok) return nullptr;
  auto p = std::make_shared<InterpretedProgram>();
  p->scene_name = std::string(r.text());
  p->model_name = std::string(r.text());
  if (!r.ok || p->scene_name != scene_name || p->model_name != model) return nullptr;
  for (int* n : {&p->n_states, &p->n_parameters, &p->n_coordinates, &p->n_multipliers, &p->n_hidden, &p->n_invariants,
                 &p->n_reference, &p->n_singular, &p->n_inputs, &p->n_speeds})
    *n = r.integer();
  ModelLayout& l = p->layout;
  l.state_names = r.texts();
  l.state_variable = r.integers();
  l.state_order = r.integers();
  l.differential_id = r.reals();
  l.residual_names = r.texts();
  l.default_parameters = r.reals();
  l.hidden_names = r.texts();
  l.invariant_names = r.texts();
  l.reference_coordinate = r.integers();
  l.singular_names = r.texts();
  l.speed_coordinate = r.integers();
  p->parameter_names = r.texts();
  p->input_names = r.texts();
  p->colptr = r.integers();
  p->rowind = r.integers();
  for (std::size_t field = 0; field < kFieldCount && r.ok; ++field) {
    InterpretedFunction& f = p->functions[field];
    const int present = r.integer();
    if (present != 0 && present != 1) return nullptr;
    if (!present) continue;
    f.present = true;
    f.zero_fill = r.integer();
    const std::string_view program = r.text();
    if (!r.ok || f.zero_fill < 0) return nullptr;
    std::optional<EvaluationProgram> lowered = EvaluationProgram::from_bytes(program, kFieldInputs[field], 1);
    if (!lowered) return nullptr;
    f.program = std::move(*lowered);
  }
  if (!r.ok || r.pos != bytes.size() || !consistent(*p)) return nullptr;
  return p;
}

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

runtime::Model interpret(std::shared_ptr<const InterpretedProgram> program) {
  auto interpreter = std::make_shared<Interpreter>(std::move(program));
  interpreter->install();
  const nhc_model_table* table = interpreter->table();
  return runtime::Model::from_table(table, std::shared_ptr<const void>(interpreter, table));
}

runtime::Model interpret(const Scene& scene, const Index1System& system, const PreparedModel& model) {
  return interpret(interpreted_program(scene, system, model));
}

}  // namespace nhc::jit
