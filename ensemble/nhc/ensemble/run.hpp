#pragma once
/// \file run.hpp
/// \brief One run of an ensemble: what every run shares (RunSpec: the model's shared object,
/// the scene's parameters and initial values, times, tolerances, which values the design
/// replaces), what a run produces (RunRecord), and run_one(), which never throws: a failing run
/// is a record with its reason.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "nhc/ensemble/bytes.hpp"
#include "nhc/runtime/model.hpp"

namespace nhc::ensemble {

/// What a design variable replaces: a parameter, or the initial value of a coordinate's (or
/// multiplier's) derivative of some order (`x'(0)`: variable x, order 1).
struct Target {
  enum class Kind : std::int32_t { parameter, initial };
  Kind kind = Kind::parameter;
  std::int32_t parameter = -1;
  std::string variable;
  std::int32_t order = 0;
  /// The scene parameter of that name when the scene's [initial] is written through it: each run
  /// evaluates those values again with the run's value (`parameter` is -1 when the model's
  /// equations do not read it, so that only the start moves). Empty otherwise.
  std::string scene_parameter;
};

/// NAME as a parameter of the model or `q(0)`, `q'(0)`, `q''(0)`… of one of its unknowns with a
/// differential state of that order. Throws InputError located at `flag` (the flag and its
/// argument, "--vary q=0:1:3"), listing the names that exist.
Target resolve_target(const runtime::Model& model, const std::string& name, const std::string& flag);

/// The names a design may vary: the parameters, then q(0), q'(0), … for every differential state.
std::vector<std::string> variable_names(const runtime::Model& model);

struct RunSpec {
  std::string shared_object;  ///< the compiled model every rank loads
  std::vector<double> parameters;
  std::map<std::string, std::vector<double>> initial;  ///< the scene's [initial]
  /// [initial] values written through parameters (InitialData::expressions, "" for a number) and
  /// every parameter's value by name: what a target's scene_parameter re-evaluates.
  std::map<std::string, std::vector<std::string>> initial_expressions;
  std::map<std::string, double> scene_parameters;
  double t0 = 0, t_end = 1;
  std::int32_t outputs = 100;  ///< output intervals: outputs + 1 sample times from t0 to t_end
  double rtol = 1e-8, atol = 1e-10;
  bool keep_trajectories = false;
  std::vector<Target> targets;  ///< one per design variable, in design order

  std::vector<double> times() const;
};

std::vector<char> encode(const RunSpec& spec);
RunSpec decode_spec(const std::vector<char>& bytes);

enum class Outcome : std::int8_t {
  pending = 0,   ///< not run yet (a checkpoint of an unfinished ensemble)
  ok = 1,        ///< reached t_end
  singular = 2,  ///< stopped at a singular point of the constraints (t_stop)
  failed = 3,    ///< any other failure; `message` says why
};
const char* to_string(Outcome outcome);

struct RunRecord {
  std::int64_t index = -1;
  Outcome outcome = Outcome::pending;
  double t_stop = 0;                    ///< the last time reached (t_end when ok)
  std::string message;                  ///< the failure, in words ("" when ok)
  std::vector<double> final_state;      ///< y at t_stop (NaN when nothing was reached)
  std::vector<double> invariant_drift;  ///< max_t |I_k(t) − I_k(t0)|
  double hidden_drift = 0;              ///< max_t max_i |g_i|
  std::int64_t steps = 0;
  double seconds = 0;     ///< wall time of the run (timing: differs between runs of one ensemble)
  std::int32_t rank = 0;  ///< the MPI rank that ran it
  /// With keep_trajectories: y at the spec's times, (outputs + 1) × n_states, NaN after t_stop.
  std::vector<double> trajectory;

  bool finished() const { return outcome != Outcome::pending; }
};

/// A pending record of `model`'s sizes: NaN values.
RunRecord pending_record(std::int64_t index, int n_states, int n_invariants);

void encode(ByteWriter& out, const RunRecord& record);
RunRecord decode_record(ByteReader& in);

/// Integrates one run: the spec's parameters and initial values with `values` (one per target)
/// put in. Catches every failure into the record.
RunRecord run_one(const runtime::Model& model, const RunSpec& spec, std::int64_t index, const double* values);

}  // namespace nhc::ensemble
