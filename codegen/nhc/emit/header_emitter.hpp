#pragma once
/// \file header_emitter.hpp
/// \brief The self-contained C++ header `nhc generate` writes for one model of a scene: metadata,
/// residual F(t, y, y') of the index-1 form, its Jacobian dF/dy + cj dF/dy' (dense or compressed
/// column), hidden constraints and their Jacobian, invariants and reference solution.
/// The layout is the contract in docs/generated-code.md.

#include <ginac/ginac.h>

#include <optional>
#include <string>
#include <vector>

#include "nhc/analysis/index1_system.hpp"
#include "nhc/emit/cse.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc {

enum class JacobianKind { dense, sparse, none };
std::string to_string(JacobianKind kind);
std::optional<JacobianKind> parse_jacobian_kind(const std::string& name);

/// The Jacobian generated when none is asked for: dense below kSparseJacobianFromStates states,
/// compressed-column from there (the dense LU's n³ then costs more than KLU's fill-in).
inline constexpr int kSparseJacobianFromStates = 40;
inline JacobianKind default_jacobian_kind(int n_states) {
  return n_states >= kSparseJacobianFromStates ? JacobianKind::sparse : JacobianKind::dense;
}

/// J = dF/dy + cj dF/dy' of the index-1 residual (SUNDIALS IDA's iteration matrix), with its
/// compressed-column structure: the entries that are not identically zero after GiNaC's
/// automatic simplification.
struct SymbolicJacobian {
  GiNaC::realsymbol cj{"cj"};
  int size = 0;
  std::vector<GiNaC::ex> entries;  ///< column-major size × size
  std::vector<int> colptr;         ///< size + 1
  std::vector<int> rowind;         ///< colptr.back()
};
SymbolicJacobian index1_jacobian(const Index1System& system);

/// G = dg/dy of the hidden constraints, column-major n_hidden × n_states.
std::vector<GiNaC::ex> hidden_constraint_jacobian(const Index1System& system);

/// The scene's invariants with every jet symbol rewritten as a state (Index1System::jet_to_state).
/// Throws MathError naming the invariant when it involves a derivative the states do not hold.
std::vector<GiNaC::ex> invariants_in_states(const Scene& scene, const Index1System& system);

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

struct HeaderOptions {
  JacobianKind jacobian = JacobianKind::dense;
  /// dF/dp and dg/dp for forward sensitivities (docs/generated-code.md, "Sensitivity additions").
  bool sensitivities = false;
};

struct GeneratedHeader {
  std::string file_name;       ///< `<scene>_<model>.hpp`
  std::string namespace_name;  ///< `<scene>_<model>`, inside `nhc_gen`
  std::string text;
  OperationCount before_cse;   ///< every emitted function evaluated as trees
  OperationCount after_cse;
};

/// Emits the header. Deterministic: the same scene, model and options give the same bytes (the
/// banner names the scene file without its directory, and no time stamp).
GeneratedHeader generate_header(const Scene& scene, const Index1System& system,
                                const HeaderOptions& options);

/// e in C++ syntax with scene names (`0.5 * m * (x' * x' + y' * y')`), the same in every run
/// (GiNaC's own printing follows its term order, which changes from run to run).
std::string scene_notation(const GiNaC::ex& e, const JetSpace& jet);

/// Text safe inside a `//` comment: one line, no `*/`, no backslash (line splicing), ASCII only.
std::string sanitize_comment(const std::string& text);
/// A C++ string literal (with quotes) for arbitrary text.
std::string cpp_string_literal(const std::string& text);

}  // namespace nhc
