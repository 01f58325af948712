#pragma once
/// \file results_file.hpp
/// \brief An ensemble in an HDF5 file (serial HDF5 C API, written by one process): the design,
/// one record per run, the settings as attributes. Layout (docs/ensemble.md):
///
///   /                 attributes: format, scene, scene_file, model, nhc_version, rtol, atol, t0,
///                     t_end, outputs, period, keep, design, seed, runs, finished; timings: ranks,
///                     threads, wall_seconds
///   /design/names     string[v]              /design/specs  string[v] (the flags' arguments)
///   /design/values    double[runs][v]        /design/grid_shape int64[v] (grids)
///   /runs/outcome     enum int8 {pending, ok, singular, failed, stopped}[runs]
///   /runs/t_stop, /runs/hidden_drift, /runs/seconds  double[runs]
///   /runs/message     string[runs]           /runs/steps int64[runs]   /runs/rank int32[runs]
///   /runs/events      string[runs] (the events met: a line "NAME,T" each)
///   /runs/final_state double[runs][states]   /runs/state_names string[states]
///   /runs/invariant_drift double[runs][invariants]  /runs/invariant_names string[invariants]
///   /trajectories/t   double[outputs+1]      /trajectories/y double[runs][outputs+1][states]
///
/// Written to a temporary file beside the target and renamed, so a reader (or a killed
/// ensemble) never sees half a file.

#include <string>
#include <vector>

#include "nhc/ensemble/design.hpp"
#include "nhc/ensemble/run.hpp"

namespace nhc::ensemble {

inline constexpr const char* kFormat = "nhc-ensemble 1";

struct EnsembleInfo {
  std::string scene, scene_file, model, nhc_version;
  /// SHA-256 of the scene's text (followed by the --initial values, when given), what every run
  /// is computed from beyond the fields below (--resume compares it, not the scene's name).
  std::string scene_digest;
  double rtol = 0, atol = 0, t0 = 0, t_end = 0;
  int outputs = 0;
  double period = 0;  ///< a sampled controller's: the output times are its samples (RunSpec::times)
  bool keep_trajectories = false;
  std::vector<std::string> state_names, invariant_names;
  Design design;
  // Timings and placement: differ between runs of the same ensemble.
  int ranks = 1, threads = 1;
  double wall_seconds = 0;
};

struct EnsembleResults {
  EnsembleInfo info;
  std::vector<RunRecord> records;  ///< one per run, by index; pending when not run yet

  long finished() const;
};

/// Writes `results` atomically, creating missing directories (nhc/io/atomic_file.hpp). Throws
/// EnvironmentError naming `path` when it cannot be written (disk full, no permission).
void write_results(const std::string& path, const EnsembleResults& results);

/// Reads a file written by write_results(). Throws InputError naming the file when it is not one.
EnsembleResults read_results(const std::string& path);

/// Throws EnvironmentError naming `path` unless write_results() could create it; creates nothing.
void check_writable(const std::string& path);

/// Why `stored` is not the same ensemble as `wanted` (scene, model, settings, design), or "".
std::string resume_mismatch(const EnsembleInfo& stored, const EnsembleInfo& wanted);

}  // namespace nhc::ensemble
