#pragma once
/// \file trajectory.hpp
/// \brief What a run produces: the samples, the quantities derived from them (hidden-constraint
/// residuals, invariants, errors against the scene's reference), their drift, and the CSV file.

#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "nhc/runtime/integrator.hpp"

namespace nhc::runtime {

/// Per-sample derived quantities, in CSV column order.
struct Observables {
  std::vector<double> hidden;      ///< g_i(t, y)
  std::vector<double> invariants;  ///< I_k(t, y, y')
  std::vector<double> errors;      ///< q_c(t) computed − reference, for the reference coordinates
};

Observables observe(const Model& model, const std::vector<double>& p, const Sample& sample);

/// The same into `o`, whose storage (and `scratch`'s) is reused from sample to sample: a loop
/// over a run's samples allocates nothing after the first (CsvRows).
void observe(const Model& model, const std::vector<double>& p, const Sample& sample, Observables& o,
             std::vector<double>& scratch);

/// Below this size along the run an invariant's drift is reported absolute (DriftReport).
inline constexpr double kInvariantScaleFloor = 1e-8;

/// Maxima along a trajectory.
struct DriftReport {
  double max_hidden = 0;                  ///< max_t max_i |g_i|
  std::vector<double> max_hidden_each;    ///< per hidden constraint
  std::vector<double> first_hidden_each;  ///< per hidden constraint, its value at the first sample
  std::vector<double> invariant_drift;    ///< max_t |I_k(t) − I_k(t0)|
  /// invariant_drift / invariant_scale, or the absolute drift when the scale is below
  /// kInvariantScaleFloor (an invariant that is zero along the run: a relative drift of a
  /// value at rounding level would be noise).
  std::vector<double> invariant_relative;
  std::vector<double> invariant_scale;   ///< max_t |I_k(t)|: the invariant's size along the run
  std::vector<bool> invariant_absolute;  ///< invariant_relative holds the absolute drift
  double max_invariant_relative = 0;
  std::vector<double> max_error_each;  ///< per reference coordinate
  double max_error = 0;
};

DriftReport measure_drift(const Model& model, const std::vector<double>& p, const std::vector<Sample>& samples);

/// The CSV header: t, states by name with the highest derivative from y' (x, x', x''), then
/// multipliers, the hidden constraints (hidden_column), invariant:<name>, error:<coordinate>.
std::vector<std::string> csv_header(const Model& model);

/// The numbers of one CSV row per sample, in csv_header's order (write_csv prints them; the
/// Python package hands them over as arrays). One object per thread: row() reuses its storage.
class CsvRows {
 public:
  CsvRows(const Model& model, std::vector<double> parameters);
  void row(const Sample& sample, std::vector<double>& out) const;

 private:
  const Model& model_;
  std::vector<double> parameters_;
  std::vector<int> top_;                     ///< per unknown: its highest differential state, or -1
  std::vector<std::vector<int>> states_of_;  ///< per unknown: its states, in state order
  mutable Observables observed_;             ///< storage reused by row()
  mutable std::vector<double> scratch_;
};

/// The CSV column of hidden constraint i: hidden:<i> (1-based) where the model enforces it; for
/// the suslov model, which only monitors the scene's constraints, constraint:<name> (f1 for the
/// scene's first constraint, as nhc derive and analyze name it).
std::string hidden_column(const Model& model, int i);

/// Writes the trajectory as CSV (17 significant digits), atomically: a temporary file beside
/// `path` renamed over it. Throws std::runtime_error when the file cannot be written.
void write_csv(const std::string& path, const Model& model, const std::vector<double>& p,
               const std::vector<Sample>& samples);
/// The same CSV text on a stream (for callers with their own atomic writing).
void write_csv(std::ostream& out, const Model& model, const std::vector<double>& p, const std::vector<Sample>& samples);

/// A whole run: initialization, integration through `times`, statistics; a SolverError is caught
/// and kept in `failure`, the samples up to the failure are kept.
struct RunResult {
  Sample initial;
  std::vector<Sample> samples;
  Statistics statistics;
  std::vector<EventHit> events;
  std::optional<base::SolverError> failure;
};

/// `inputs`: u(t, y) for the model's inputs (inputs.hpp); empty: their default signals.
RunResult simulate(const Model& model, const std::vector<double>& p, const InitialState& initial,
                   const std::vector<double>& times, const IntegratorOptions& options = {},
                   const std::vector<Event>& events = {}, const InputFunction& inputs = {});

}  // namespace nhc::runtime
