/* nhc runtime: the C table through which a compiled model is loaded from a shared object.
 * The one definition: every header `nhc generate` writes embeds this file verbatim (taken at
 * build time, docs/generated-code.md), hand-written models include it; the guard keeps a second
 * copy out. Fill it by field name (zero-initialize, then assign), never by position.
 * abi_version 1: the fields up to `reference`. abi_version 2 appends the fields of the section
 * "Runtime additions" of docs/generated-code.md; read them only when abi_version >= 2.
 * abi_version 3 appends the "Sensitivity additions"; read them only when abi_version >= 3.
 * abi_version 4 appends the "Input additions"; read them only when abi_version >= 4.
 * abi_version 5 appends the "Variational additions"; read them only when abi_version >= 5.
 * abi_version 6 appends the "Reduced-form additions"; read them only when abi_version >= 6. */
#ifndef NHC_MODEL_TABLE_DEFINED
#define NHC_MODEL_TABLE_DEFINED

#ifdef __cplusplus
extern "C" {
#endif

struct nhc_model_table {
  int abi_version;
  const char* scene_name;
  const char* model_name;
  int n_states, n_parameters, n_coordinates, n_multipliers, n_hidden, n_invariants, n_reference;
  const char* const* state_names;
  const int* state_variable;
  const int* state_order;
  const double* differential_id;
  const char* const* parameter_names;
  const double* default_parameters;
  const char* const* hidden_names;
  const char* const* invariant_names;
  const int* reference_coordinate;
  void (*residual)(double, const double*, const double*, const double*, double*);
  void (*jacobian)(double, const double*, const double*, double, const double*, double*);
  int jacobian_nnz;
  const int* jacobian_colptr;
  const int* jacobian_rowind;
  void (*jacobian_values)(double, const double*, const double*, double, const double*, double*);
  void (*hidden_constraints)(double, const double*, const double*, double*);
  void (*hidden_constraints_jacobian)(double, const double*, const double*, double*);
  void (*invariants)(double, const double*, const double*, const double*, double*);
  void (*reference)(double, const double*, double*);
  /* abi_version >= 2 (Runtime additions) */
  const char* const* residual_names;
  int n_singular;
  const char* const* singular_names;
  void (*singular_quantities)(double, const double*, const double*, double*);
  /* abi_version >= 3 (Sensitivity additions; null unless generated with sensitivities) */
  void (*residual_parameter_jacobian)(double, const double*, const double*, const double*, double*);
  void (*hidden_parameter_jacobian)(double, const double*, const double*, double*);
  /* abi_version >= 4 (Input additions): p holds n_parameters parameters, then n_inputs inputs */
  int n_inputs;
  const char* const* input_names;
  void (*default_inputs)(double, const double*, double*);
  /* abi_version >= 5 (Variational additions; null unless generated with them): the discrete
   * Lagrange-d'Alembert step of docs/variational.md, in x = (q_{k+1} - q_k, lambda_k) */
  void (*momentum)(double, const double*, const double*, double*);
  void (*variational_residual)(double, double, double, const double*, const double*, const double*, const double*,
                               const double*, double*);
  void (*variational_jacobian)(double, double, double, const double*, const double*, const double*, const double*,
                               const double*, double*);
  void (*variational_momentum)(double, double, const double*, const double*, const double*, double*);
  /* abi_version >= 6 (Reduced-form additions; n_speeds = 0 and null functions where the model has
   * no multiplier-free form): M_r(t, q, u) u' = f_r(t, q, u) on the independent speeds
   * u = q'[speed_coordinate[k]] (docs/reduced-form.md); each function reads (t, q, u, p) */
  int n_speeds;
  const int* speed_coordinate;
  void (*velocities)(double, const double*, const double*, const double*, double*);
  void (*mass_matrix)(double, const double*, const double*, const double*, double*);
  void (*forcing)(double, const double*, const double*, const double*, double*);
};

#ifdef __cplusplus
}
#endif

#endif /* NHC_MODEL_TABLE_DEFINED */
