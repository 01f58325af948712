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
#include "nhc/expr/expression_dag.hpp"
#include "nhc/emit/model_preparation.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc {

enum class JacobianKind { dense, sparse, none };
struct ReducedForm;  // derive/reduced_form.hpp
std::string to_string(JacobianKind kind);
std::optional<JacobianKind> parse_jacobian_kind(const std::string& name);

/// The Jacobian generated when none is asked for: dense below kSparseJacobianFromStates states,
/// compressed-column from there (the dense LU's n³ then costs more than KLU's fill-in).
inline constexpr int kSparseJacobianFromStates = 40;
inline JacobianKind default_jacobian_kind(int n_states) {
  return n_states >= kSparseJacobianFromStates ? JacobianKind::sparse : JacobianKind::dense;
}

struct HeaderOptions {
  JacobianKind jacobian = JacobianKind::dense;
  /// dF/dp and dg/dp for forward sensitivities (docs/generated-code.md, "Sensitivity additions").
  bool sensitivities = false;
  /// The discrete Lagrange–d'Alembert step of the chetaev model for `--integrator variational`
  /// (docs/generated-code.md, "Variational additions"; docs/variational.md).
  bool variational = false;
  /// From this many bytes of function text, the header carries the NHC_PART protocol and may be
  /// compiled as several translation units (docs/generated-code.md): below it a second
  /// compiler's fixed cost outweighs the halved optimization (bench/compile-time.md), and the
  /// small header stays free of it. 0: always.
  std::size_t split_from_bytes = 100000;
  /// The multiplier-free form (derive/reduced_form.hpp): when given and available, the header
  /// carries velocities, mass_matrix and forcing (docs/generated-code.md, "Reduced-form additions").
  const ReducedForm* reduced = nullptr;
};

struct GeneratedHeader {
  std::string file_name;       ///< `<scene>_<model>.hpp`
  std::string namespace_name;  ///< `<scene>_<model>`, inside `nhc_gen`
  std::string text;
  OperationCount before_cse;  ///< every emitted function evaluated as trees
  OperationCount after_cse;
};

/// The namespace (inside `nhc_gen`) and the file name of the header of `model` of a scene named
/// `scene_name`: `<scene>_<model>` and `<scene>_<model>.hpp` (docs/generated-code.md). The one
/// place these names are made; `nhc generate --print-file-name` prints the second, so that build
/// systems (nhc_add_model) never reconstruct it.
std::string generated_namespace_name(const std::string& scene_name, ModelKind model);
std::string generated_header_file_name(const std::string& scene_name, ModelKind model);

/// Emits the header. Deterministic: the same scene, model and options give the same bytes (the
/// banner names the scene file without its directory, and no time stamp).
/// `prepared`, when given, receives the model the header was printed from (what an interpreted
/// model runs, nhc/jit/interpreted_model.hpp).
GeneratedHeader generate_header(const Scene& scene, const Index1System& system, const HeaderOptions& options,
                                PreparedModel* prepared = nullptr);

/// Text safe inside a `//` comment: one line, no `*/`, no backslash (line splicing), ASCII only.
std::string sanitize_comment(const std::string& text);
/// A C++ string literal (with quotes) for arbitrary text.
std::string cpp_string_literal(const std::string& text);

}  // namespace nhc
