// One run of an ensemble (run.hpp).
#include "nhc/ensemble/run.hpp"

#include "nhc/base/primed_name.hpp"

#include <algorithm>
#include <chrono>
#include <new>
#include <cmath>
#include <limits>

#include "nhc/errors.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/base/number_text.hpp"

namespace nhc::ensemble {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string initial_name(const std::string& variable, int order) { return base::primed_name(variable, order) + "(0)"; }

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

}  // namespace

std::vector<std::string> variable_names(const runtime::Model& model, const std::vector<std::string>& parameters) {
  std::vector<std::string> names = parameters;
  for (int i = 0; i < model.n_states(); ++i)
    if (model.is_differential(i))
      names.push_back(initial_name(model.variable_name(model.table().state_variable[i]), model.table().state_order[i]));
  return names;
}

Target resolve_initial_target(const runtime::Model& model, const std::vector<std::string>& parameters,
                              const std::string& name, const std::string& flag) {
  // q(0), q'(0), q''(0), …
  auto unknown = [&]() -> Target {
    throw InputError({flag, 0, 0}, "unknown name '" + name + "'; " + model.scene_name() + " (" + model.model_name() +
                                       ") has " + joined(variable_names(model, parameters)));
  };
  if (name.size() < 4 || name.compare(name.size() - 3, 3, "(0)") != 0) return unknown();
  std::string base = name.substr(0, name.size() - 3);
  int order = 0;
  while (!base.empty() && base.back() == '\'') {
    base.pop_back();
    ++order;
  }
  const int unknowns = model.n_coordinates() + model.n_multipliers();
  for (int v = 0; v < unknowns; ++v)
    if (model.variable_name(v) == base) {
      const int state = model.state_index(v, order);
      if (state < 0 || !model.is_differential(state)) return unknown();
      Target target;
      target.kind = Target::Kind::initial;
      target.variable = base;
      target.order = order;
      return target;
    }
  return unknown();
}

std::vector<double> RunSpec::times() const {
  if (period <= 0) return runtime::output_times(t0, t_end, outputs);
  std::vector<double> times;  // as the controller's samples are computed (app::sample_times)
  for (std::int32_t k = 0; k <= outputs; ++k) times.push_back(t0 + static_cast<double>(k) * period);
  return times;
}

std::vector<char> encode(const RunSpec& spec) {
  ByteWriter out;
  out.put(spec.shared_object);
  out.put(spec.sliding_object);
  out.put(spec.scene_text);
  out.put(spec.t0);
  out.put(spec.t_end);
  out.put(spec.outputs);
  out.put(spec.period);
  out.put(spec.rtol);
  out.put(spec.atol);
  out.put(static_cast<std::int8_t>(spec.keep_trajectories));
  out.put<std::uint64_t>(spec.targets.size());
  for (const Target& t : spec.targets) {
    out.put(t.kind);
    out.put(t.name);
    out.put(t.variable);
    out.put(t.order);
  }
  return std::move(out.bytes());
}

RunSpec decode_spec(const std::vector<char>& bytes) {
  ByteReader in(bytes);
  RunSpec spec;
  spec.shared_object = in.get_string();
  spec.sliding_object = in.get_string();
  spec.scene_text = in.get_string();
  spec.t0 = in.get<double>();
  spec.t_end = in.get<double>();
  spec.outputs = in.get<std::int32_t>();
  spec.period = in.get<double>();
  spec.rtol = in.get<double>();
  spec.atol = in.get<double>();
  spec.keep_trajectories = in.get<std::int8_t>() != 0;
  const auto n_targets = in.get<std::uint64_t>();
  for (std::uint64_t k = 0; k < n_targets; ++k) {
    Target t;
    t.kind = in.get<Target::Kind>();
    t.name = in.get_string();
    t.variable = in.get_string();
    t.order = in.get<std::int32_t>();
    spec.targets.push_back(t);
  }
  return spec;
}

const char* to_string(Outcome outcome) {
  switch (outcome) {
    case Outcome::pending:
      return "pending";
    case Outcome::ok:
      return "ok";
    case Outcome::singular:
      return "singular";
    case Outcome::failed:
      return "failed";
    case Outcome::stopped:
      return "stopped";
  }
  return "?";
}

RunRecord pending_record(std::int64_t index, int n_states, int n_invariants) {
  RunRecord r;
  r.index = index;
  r.t_stop = kNaN;
  r.final_state.assign(static_cast<std::size_t>(n_states), kNaN);
  r.invariant_drift.assign(static_cast<std::size_t>(n_invariants), kNaN);
  r.hidden_drift = kNaN;
  r.seconds = kNaN;
  r.rank = -1;
  return r;
}

void encode(ByteWriter& out, const RunRecord& r) {
  out.put(r.index);
  out.put(r.outcome);
  out.put(r.t_stop);
  out.put(r.message);
  out.put(r.events);
  out.put(r.final_state);
  out.put(r.invariant_drift);
  out.put(r.hidden_drift);
  out.put(r.steps);
  out.put(r.seconds);
  out.put(r.rank);
  out.put(r.trajectory);
}

RunRecord decode_record(ByteReader& in) {
  RunRecord r;
  r.index = in.get<std::int64_t>();
  r.outcome = in.get<Outcome>();
  r.t_stop = in.get<double>();
  r.message = in.get_string();
  r.events = in.get_string();
  r.final_state = in.get_vector<double>();
  r.invariant_drift = in.get_vector<double>();
  r.hidden_drift = in.get<double>();
  r.steps = in.get<std::int64_t>();
  r.seconds = in.get<double>();
  r.rank = in.get<std::int32_t>();
  r.trajectory = in.get_vector<double>();
  return r;
}

RunRecord run_one(const runtime::Model& model, const RunSpec& spec, std::int64_t index, const double* values,
                  const MemberFunction& member) {
  const auto start = std::chrono::steady_clock::now();
  RunRecord record = pending_record(index, model.n_states(), model.n_invariants());
  const std::vector<double> times = spec.times();
  const std::size_t n = static_cast<std::size_t>(model.n_states());
  if (spec.keep_trajectories) record.trajectory.assign(times.size() * n, kNaN);
  record.outcome = Outcome::failed;
  try {
    const MemberRun made = member(values);
    const runtime::RunResult& run = made.run;
    // The rows at the output times (the engine reports them exactly); a row between them (the
    // point where an event ended the run or the integration failed) is kept only as the final state.
    std::size_t next = 0;
    for (const runtime::Sample& s : run.samples) {
      while (next < times.size() && times[next] < s.t) ++next;
      if (!record.trajectory.empty() && next < times.size() && times[next] == s.t && s.y.size() == n)
        std::copy(s.y.begin(), s.y.end(), record.trajectory.begin() + static_cast<long>(next * n));
    }
    if (!run.samples.empty()) {
      record.final_state = run.samples.back().y;
      record.t_stop = run.samples.back().t;
      const runtime::DriftReport drift = runtime::measure_drift(model, made.p, made.drift_samples);
      if (!made.drift_samples.empty()) {
        record.invariant_drift = drift.invariant_drift;
        record.hidden_drift = drift.max_hidden;
      }
    }
    for (const runtime::EventHit& hit : run.events)
      record.events += hit.name + "," + base::number_text(hit.t, 17) + "\n";
    record.steps = run.statistics.steps;
    if (run.failure) {
      const base::SolverError& e = *run.failure;
      record.outcome =
          e.kind() == base::FailureKind::singular_constraint_gradient ? Outcome::singular : Outcome::failed;
      record.message = e.what();
      if (run.samples.empty() || std::isfinite(e.t())) record.t_stop = e.t();
    } else if (!run.samples.empty() && run.samples.back().t < times.back()) {
      // Ended before the last output time without a failure: an event that stops the run (or a
      // contact's slip) ended it, at the last event met.
      record.outcome = Outcome::stopped;
      record.message = run.events.empty() ? "stopped at t = " + base::number_text(record.t_stop, 12)
                                          : "stopped by event " + run.events.back().name +
                                                " at t = " + base::number_text(run.events.back().t, 12);
    } else {
      record.outcome = Outcome::ok;
    }
  } catch (const std::bad_alloc&) {
    record.outcome = Outcome::failed;
    record.message = "out of memory";
  } catch (const std::exception& e) {
    record.outcome = Outcome::failed;
    record.message = e.what();
  } catch (...) {
    record.outcome = Outcome::failed;
    record.message = "unknown failure";
  }
  record.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return record;
}

}  // namespace nhc::ensemble
