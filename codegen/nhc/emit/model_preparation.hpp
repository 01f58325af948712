#pragma once
/// \file model_preparation.hpp
/// \brief The symbolic half of the header emitter: everything a generated header computes,
/// prepared before any text is printed — the Jacobian of the index-1 residual, the
/// hidden-constraint Jacobian (the one Index1System holds), the invariants in states, the
/// singular quantities — and every emitted function lowered into one instruction list with
/// common subexpressions shared (expr/expression_dag.hpp). header_printer.hpp turns a PreparedModel into text.

#include <ginac/ginac.h>

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "nhc/analysis/index1_system.hpp"
#include "nhc/expr/cpp_printer.hpp"
#include "nhc/expr/expression_dag.hpp"
#include "nhc/expr/stable_symbol.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc {

enum class JacobianKind;  // header_emitter.hpp
struct ReducedForm;       // derive/reduced_form.hpp

/// J = dF/dy + cj dF/dy' of the index-1 residual (SUNDIALS IDA's iteration matrix), with its
/// compressed-column structure: the entries that are not identically zero after GiNaC's
/// automatic simplification.
struct SymbolicJacobian {
  GiNaC::realsymbol cj = stable_symbol("cj");
  int size = 0;
  std::vector<int> colptr;        ///< size + 1
  std::vector<int> rowind;        ///< colptr.back()
  std::vector<GiNaC::ex> values;  ///< the entries of rowind, in the same order (no dense copy:
                                  ///< at N = 1024 knives size² expressions took 400 MB)
  /// The entry (i, j): a value, or 0 outside the pattern.
  GiNaC::ex entry(int i, int j) const;
};
SymbolicJacobian index1_jacobian(const Index1System& system);

/// An invariant of the scene as the model computes it.
struct ModelInvariant {
  std::string name;
  GiNaC::ex in_states;  ///< every jet symbol rewritten as a state (Index1System::jet_to_state)
};
/// The scene's invariants this model computes. One that involves a quantity the states do not
/// hold (a multiplier of the suslov model, λ' where λ is algebraic) is left out, and the run
/// says so (cli/scene_outputs.hpp); a `required` one is an InputError at its expression instead.
std::vector<ModelInvariant> invariants_in_states(const Scene& scene, const Index1System& system);

/// A quantity whose zeros make the equations singular (runtime additions of
/// docs/generated-code.md): the base of a square root or negative power, or the argument of a
/// logarithm, occurring in the residuals or hidden constraints and depending on the states y
/// (not on y'). `name` is the quantity in scene notation (`x' * x' + y' * y'`). Each quantity
/// once, in an order that is the same in every run.
struct SingularQuantity {
  std::string name;
  GiNaC::ex expression;  ///< in t, p, y
};
std::vector<SingularQuantity> singular_quantities(const Index1System& system);

/// A monitor of each of the scene's Euler angles (Scene::euler_chains) whose angles are states:
/// sin or cos of the middle angle, named `Euler angles psi, th, ph (z-x-z), singular at th = 0, pi`
/// (the form docs/generated-code.md gives, which the runtime reads). They follow
/// singular_quantities() in the model's monitors; the runtime does not stop at their zeros (a
/// scene may determine the rates otherwise) but names the angle when a run fails near one.
std::vector<SingularQuantity> euler_angle_monitors(const Scene& scene, const Index1System& system);

/// Each expression in C++ syntax with scene names (`0.5 * m * (x' * x' + y' * y')`), the same in
/// every run (GiNaC's own printing follows its term order, which changes from run to run).
std::vector<std::string> scene_notation(const std::vector<GiNaC::ex>& expressions, const JetSpace& jet);

/// One emitted function: its signature parameters, the assignments (outputs as instructions
/// of PreparedModel::dag) and their operation counts.
struct FunctionPlan {
  std::string name;
  std::string doc;
  /// (type, name) in order; a name the body does not read is printed as a comment.
  std::vector<std::pair<std::string, std::string>> parameters;
  std::vector<Assignment> assignments;
  std::string prologue;  ///< e.g. zero fill of a dense matrix
  int zero_fill = 0;     ///< the output's first entries the prologue sets to zero
  OperationCount before, after;
};

/// A model ready to print: sizes, names, the Jacobian's structure and the functions.
struct PreparedModel {
  std::string model;           ///< the model's name (to_string(ModelKind))
  std::string namespace_name;  ///< `<scene>_<model>`
  JacobianKind jacobian;
  bool sensitivities = false;  ///< dF/dp and dg/dp emitted
  bool variational = false;    ///< the discrete Lagrange–d'Alembert step emitted
  int n_states = 0, n_parameters = 0, n_coordinates = 0, n_multipliers = 0, n_hidden = 0;
  int n_invariants = 0, n_reference = 0, n_singular = 0;
  /// The scene's parameters the functions read, by index into the scene's list, in its order:
  /// p[k] of the header is scene parameter parameters[k]. One that no equation, invariant or
  /// reference uses does not reach the header (a scene may carry thousands).
  std::vector<int> parameters;
  std::vector<std::string> parameter_names;  ///< their names, in the same order
  /// The scene's inputs ([inputs]), all of them in scene order: p[n_parameters + k] of the
  /// header is input k (docs/generated-code.md, "Input additions").
  int n_inputs = 0;
  std::vector<std::string> input_names;
  std::vector<ModelInvariant> invariants;  ///< the scene's invariants this model computes
  SceneReference::Entries reference;       ///< the scene's closed forms for this model
  SymbolicJacobian symbolic_jacobian;      ///< empty for JacobianKind::none
  std::vector<SingularQuantity> singular;
  /// The multiplier-free form's independent speeds (Reduced-form additions of
  /// docs/generated-code.md): u[k] is the first derivative of coordinate speed_coordinate[k].
  int n_speeds = 0;
  std::vector<int> speed_coordinate;
  /// Every function's assignments lowered into this one DAG, in the order the functions are
  /// printed: a subexpression is one instruction wherever it occurs.
  ExpressionDag dag{{}};
  std::vector<FunctionPlan> functions;
  OperationCount before_cse, after_cse;  ///< summed over the functions

  bool has_function(const std::string& name) const;
};

/// The symbolic preparation of the header of `system` (an index-1 form of `scene`);
/// `sensitivities`: also dF/dp and dg/dp (docs/generated-code.md, "Sensitivity additions");
/// `variational`: also the discrete Lagrange–d'Alembert step of the chetaev model ("Variational
/// additions"; an InputError for another model or a scene the method does not take);
/// `reduced`: when given and available, also velocities, mass_matrix and forcing of the
/// multiplier-free form ("Reduced-form additions").
PreparedModel prepare_model(const Scene& scene, const Index1System& system, JacobianKind jacobian,
                            bool sensitivities = false, bool variational = false, const ReducedForm* reduced = nullptr);

}  // namespace nhc
