// One run of an ensemble (run.hpp).
#include "nhc/ensemble/run.hpp"

#include "nhc/base/primed_name.hpp"

#include <new>
#include <chrono>
#include <cmath>
#include <limits>

#include "nhc/errors.hpp"
#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/constant_expression.hpp"

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

std::vector<std::string> variable_names(const runtime::Model& model) {
  std::vector<std::string> names;
  for (int k = 0; k < model.n_parameters(); ++k) names.push_back(model.table().parameter_names[k]);
  for (int i = 0; i < model.n_states(); ++i)
    if (model.is_differential(i))
      names.push_back(initial_name(model.variable_name(model.table().state_variable[i]), model.table().state_order[i]));
  return names;
}

Target resolve_target(const runtime::Model& model, const std::string& name, const std::string& flag) {
  Target target;
  const int p = model.parameter_index(name);
  if (p >= 0) {
    target.parameter = p;
    return target;
  }
  // q(0), q'(0), q''(0), …
  auto unknown = [&]() -> Target {
    throw InputError({flag, 0, 0}, "unknown name '" + name + "'; " + model.scene_name() + " (" + model.model_name() +
                                       ") has " + joined(variable_names(model)));
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
      target.kind = Target::Kind::initial;
      target.variable = base;
      target.order = order;
      return target;
    }
  return unknown();
}

std::vector<double> RunSpec::times() const { return runtime::output_times(t0, t_end, outputs); }

std::vector<char> encode(const RunSpec& spec) {
  ByteWriter out;
  out.put(spec.shared_object);
  out.put(spec.parameters);
  out.put<std::uint64_t>(spec.initial.size());
  for (const auto& [name, values] : spec.initial) {
    out.put(name);
    out.put(values);
  }
  out.put(spec.t0);
  out.put(spec.t_end);
  out.put(spec.outputs);
  out.put(spec.rtol);
  out.put(spec.atol);
  out.put(static_cast<std::int8_t>(spec.keep_trajectories));
  out.put<std::uint64_t>(spec.targets.size());
  for (const Target& t : spec.targets) {
    out.put(t.kind);
    out.put(t.parameter);
    out.put(t.variable);
    out.put(t.order);
    out.put(t.scene_parameter);
  }
  out.put<std::uint64_t>(spec.initial_expressions.size());
  for (const auto& [name, texts] : spec.initial_expressions) {
    out.put(name);
    out.put<std::uint64_t>(texts.size());
    for (const std::string& text : texts) out.put(text);
  }
  out.put<std::uint64_t>(spec.scene_parameters.size());
  for (const auto& [name, value] : spec.scene_parameters) {
    out.put(name);
    out.put(value);
  }
  return std::move(out.bytes());
}

RunSpec decode_spec(const std::vector<char>& bytes) {
  ByteReader in(bytes);
  RunSpec spec;
  spec.shared_object = in.get_string();
  spec.parameters = in.get_vector<double>();
  const auto n_initial = in.get<std::uint64_t>();
  for (std::uint64_t k = 0; k < n_initial; ++k) {
    std::string name = in.get_string();
    spec.initial[name] = in.get_vector<double>();
  }
  spec.t0 = in.get<double>();
  spec.t_end = in.get<double>();
  spec.outputs = in.get<std::int32_t>();
  spec.rtol = in.get<double>();
  spec.atol = in.get<double>();
  spec.keep_trajectories = in.get<std::int8_t>() != 0;
  const auto n_targets = in.get<std::uint64_t>();
  for (std::uint64_t k = 0; k < n_targets; ++k) {
    Target t;
    t.kind = in.get<Target::Kind>();
    t.parameter = in.get<std::int32_t>();
    t.variable = in.get_string();
    t.order = in.get<std::int32_t>();
    t.scene_parameter = in.get_string();
    spec.targets.push_back(t);
  }
  const auto n_expressions = in.get<std::uint64_t>();
  for (std::uint64_t k = 0; k < n_expressions; ++k) {
    std::string name = in.get_string();
    const auto count = in.get<std::uint64_t>();
    std::vector<std::string>& texts = spec.initial_expressions[name];
    for (std::uint64_t j = 0; j < count; ++j) texts.push_back(in.get_string());
  }
  const auto n_parameters = in.get<std::uint64_t>();
  for (std::uint64_t k = 0; k < n_parameters; ++k) {
    std::string name = in.get_string();
    spec.scene_parameters[name] = in.get<double>();
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
  r.final_state = in.get_vector<double>();
  r.invariant_drift = in.get_vector<double>();
  r.hidden_drift = in.get<double>();
  r.steps = in.get<std::int64_t>();
  r.seconds = in.get<double>();
  r.rank = in.get<std::int32_t>();
  r.trajectory = in.get_vector<double>();
  return r;
}

namespace {

/// Running maxima of the drift and the last sample, from the samples the integrator reports.
struct RunObserver {
  const runtime::Model& model;
  const std::vector<double>& p;
  const std::vector<double>& times;
  RunRecord& record;
  std::vector<double> invariants0;
  std::size_t next_time = 0;
  bool seen = false;

  void start(const runtime::Sample& initial) {
    invariants0 = runtime::observe(model, p, initial).invariants;
    std::fill(record.invariant_drift.begin(), record.invariant_drift.end(), 0.0);
    record.hidden_drift = 0;
  }

  void operator()(const runtime::Sample& s) {
    const runtime::Observables o = runtime::observe(model, p, s);
    for (std::size_t k = 0; k < o.invariants.size(); ++k)
      record.invariant_drift[k] = std::max(record.invariant_drift[k], std::abs(o.invariants[k] - invariants0[k]));
    for (double g : o.hidden) record.hidden_drift = std::max(record.hidden_drift, std::abs(g));
    record.final_state = s.y;
    record.t_stop = s.t;
    seen = true;
    // Samples at the output times (the integrator reports them exactly); the last point reached
    // before a failure lies between two of them and is kept only as the final state.
    while (next_time < times.size() && times[next_time] < s.t) ++next_time;
    if (!record.trajectory.empty() && next_time < times.size() && times[next_time] == s.t)
      std::copy(s.y.begin(), s.y.end(), record.trajectory.begin() + static_cast<long>(next_time * s.y.size()));
  }
};

}  // namespace

RunRecord run_one(const runtime::Model& model, const RunSpec& spec, std::int64_t index, const double* values) {
  const auto start = std::chrono::steady_clock::now();
  RunRecord record = pending_record(index, model.n_states(), model.n_invariants());
  const std::vector<double> times = spec.times();
  if (spec.keep_trajectories) record.trajectory.assign(times.size() * static_cast<std::size_t>(model.n_states()), kNaN);
  std::vector<double> p = spec.parameters;
  std::map<std::string, std::vector<double>> initial = spec.initial;
  // The parameters first, then the [initial] values written through the varied ones, then the
  // initial values the design sets itself.
  std::map<std::string, double> names = spec.scene_parameters;
  bool start_moves = false;
  for (std::size_t k = 0; k < spec.targets.size(); ++k) {
    const Target& t = spec.targets[k];
    if (t.kind != Target::Kind::parameter) continue;
    if (t.parameter >= 0) p[static_cast<std::size_t>(t.parameter)] = values[k];
    if (!t.scene_parameter.empty()) names[t.scene_parameter] = values[k], start_moves = true;
  }
  if (start_moves) {
    try {
      for (const auto& [name, texts] : spec.initial_expressions) {
        std::vector<double>& v = initial[name];
        for (std::size_t j = 0; j < texts.size() && j < v.size(); ++j)
          if (!texts[j].empty()) v[j] = evaluate_constant_expression(texts[j], names);
      }
    } catch (const std::exception& e) {
      record.outcome = Outcome::failed;
      record.message = std::string("[initial] at the run's parameters: ") + e.what();
      return record;
    }
  }
  for (std::size_t k = 0; k < spec.targets.size(); ++k) {
    const Target& t = spec.targets[k];
    if (t.kind == Target::Kind::parameter) continue;
    std::vector<double>& v = initial[t.variable];
    if (v.size() <= static_cast<std::size_t>(t.order)) v.resize(static_cast<std::size_t>(t.order) + 1, 0.0);
    v[static_cast<std::size_t>(t.order)] = values[k];
  }
  RunObserver observer{model, p, times, record, {}, 0, false};
  runtime::IntegratorOptions options;
  options.rtol = spec.rtol;
  options.atol = spec.atol;
  record.outcome = Outcome::failed;
  try {
    runtime::Integrator integrator(model, p, options);
    try {
      const runtime::Sample initial_point =
          integrator.initialize(runtime::initial_state_from(model, spec.t0, initial), times.at(1));
      observer.start(initial_point);
      integrator.integrate(times, std::ref(observer));
      record.outcome = Outcome::ok;
    } catch (const base::SolverError& e) {
      record.outcome =
          e.kind() == base::FailureKind::singular_constraint_gradient ? Outcome::singular : Outcome::failed;
      record.message = e.what();
      if (!observer.seen || std::isfinite(e.t())) record.t_stop = e.t();
    }
    record.steps = integrator.statistics().steps;
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
