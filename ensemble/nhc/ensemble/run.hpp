#pragma once
/// \file run.hpp
/// \brief One run of an ensemble: what every run shares (RunSpec: the model's shared object,
/// the scene, times, tolerances, which values the design replaces), what a run produces
/// (RunRecord), and run_one(), which never throws: a failing run is a record with its reason.

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "nhc/ensemble/bytes.hpp"
#include "nhc/runtime/model.hpp"
#include "nhc/runtime/trajectory.hpp"

namespace nhc::ensemble {

/// What a design variable replaces: a parameter of the scene (by name: each run sets it as
/// `nhc simulate --set` does), or the initial value of a coordinate's (or multiplier's) derivative
/// of some order (`x'(0)`: variable x, order 1; each run writes it into [initial] as --initial
/// does).
struct Target {
  enum class Kind : std::int32_t { parameter, initial };
  Kind kind = Kind::parameter;
  std::string name;  ///< the parameter
  std::string variable;
  std::int32_t order = 0;
};

/// `q(0)`, `q'(0)`, `q''(0)`… of one of the model's unknowns with a differential state of that
/// order. Throws InputError located at `flag` (the flag and its argument, "--vary q=0:1:3"),
/// listing the names that exist (`parameters`, then the model's initial values).
Target resolve_initial_target(const runtime::Model& model, const std::vector<std::string>& parameters,
                              const std::string& name, const std::string& flag);

/// The names a design may vary: `parameters`, then q(0), q'(0), … for every differential state.
std::vector<std::string> variable_names(const runtime::Model& model, const std::vector<std::string>& parameters);

struct RunSpec {
  std::string shared_object;   ///< the compiled model every rank loads
  std::string sliding_object;  ///< the sliding model of the scene's sliding contact ("" when none)
  std::string scene_text;      ///< the scene every rank reads (with its --initial values put in again)
  double t0 = 0, t_end = 1;
  /// Output intervals: outputs + 1 sample times from t0 to t_end; under a sampled controller
  /// (period > 0) its samples t0 + k period, k = 0 … outputs.
  std::int32_t outputs = 100;
  double period = 0;
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
  stopped = 4,   ///< ended by an event or a contact's slip (t_stop; `message` names it)
};
const char* to_string(Outcome outcome);

struct RunRecord {
  std::int64_t index = -1;
  Outcome outcome = Outcome::pending;
  double t_stop = 0;                    ///< the last time reached (t_end when ok)
  std::string message;                  ///< the failure or the stop, in words ("" when ok)
  std::string events;                   ///< the events met, a line "NAME,T" each (T to 17 digits)
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

/// What one run produced: the run engine's rows, events, statistics and failure; the rows its
/// drift is measured over (those where its model's constraints hold); its parameters.
struct MemberRun {
  runtime::RunResult run;
  std::vector<runtime::Sample> drift_samples;
  std::vector<double> p;
};

/// Makes the run at the design's values (one per target): what the command's engine does.
using MemberFunction = std::function<MemberRun(const double* values)>;

/// One run: `member(values)` made into its record: the rows at the spec's times (NaN after
/// t_stop), the final state, the drift, the outcome. Catches every failure into the record.
RunRecord run_one(const runtime::Model& model, const RunSpec& spec, std::int64_t index, const double* values,
                  const MemberFunction& member);

}  // namespace nhc::ensemble
