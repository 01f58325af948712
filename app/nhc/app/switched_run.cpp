#include "nhc/app/switched_run.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "nhc/app/contact_forces.hpp"
#include "nhc/app/sample_expressions.hpp"
#include "nhc/app/scene_events.hpp"
#include "nhc/errors.hpp"
#include "nhc/expr/intermediate.hpp"
#include "nhc/runtime/number_text.hpp"

namespace nhc::app {

namespace {

bool uses_multiplier(const Scene& scene, const GiNaC::ex& e) {
  for (const JetCoordinate& c : scene.jet->jet_coordinates_in(e))
    if (c.kind == VariableKind::multiplier) return true;
  return false;
}

std::string printed(const GiNaC::ex& e) {
  std::ostringstream out;
  out << expand_intermediates(e);
  return out.str();
}

/// The multiplier number of a state name "lambda<N>", else 0.
int multiplier_number(const std::string& name) {
  if (name.rfind("lambda", 0) != 0 || name.size() == 6) return 0;
  for (std::size_t i = 6; i < name.size(); ++i)
    if (name[i] < '0' || name[i] > '9') return 0;
  return std::stoi(name.substr(6));
}

/// Where the rolling model's states are found in the sliding model's (by name; the multipliers
/// of the remaining constraints renumbered), or which friction component they are.
struct Layout {
  std::vector<int> from;      ///< sliding state index, or -1
  std::vector<int> friction;  ///< index into the contact's rolling constraints, or -1
};

Layout layout_of(const SceneContact& contact, const runtime::Model& rolling, const runtime::Model& sliding) {
  std::map<std::string, int> sliding_states;
  for (int j = 0; j < sliding.n_states(); ++j) sliding_states[sliding.state_name(j)] = j;
  Layout l;
  for (int i = 0; i < rolling.n_states(); ++i) {
    std::string name = rolling.state_name(i);
    int friction = -1;
    if (const int a = multiplier_number(name); a > 0) {
      const auto at = std::find(contact.rolling.begin(), contact.rolling.end(), a - 1);
      if (at != contact.rolling.end()) {
        friction = static_cast<int>(at - contact.rolling.begin());
      } else {
        int below = 0;
        for (int k : contact.rolling) below += k < a - 1 ? 1 : 0;
        name = "lambda" + std::to_string(a - below);
      }
    }
    const auto found = sliding_states.find(name);
    l.from.push_back(friction < 0 && found != sliding_states.end() ? found->second : -1);
    l.friction.push_back(friction);
  }
  return l;
}

}  // namespace

const SceneContact* sliding_contact(const Scene& scene) {
  const SceneContact* found = nullptr;
  for (const SceneContact& contact : scene.contacts) {
    if (contact.on_slip != SlipAction::slide) continue;
    if (found)
      throw InputError(contact.on_slip_where, "contact '" + contact.name + "': one contact of a scene may slide (on_slip = \"slide\"); '" +
                                                  found->name + "' does already");
    if (uses_multiplier(scene, contact.normal) || scene.jet->highest_coordinate_order(contact.normal) > 1)
      throw InputError(contact.on_slip_where,
                       "contact '" + contact.name + "': on_slip = \"slide\" needs the normal force as an expression of t, "
                       "q and q' (the sliding model's Coulomb force is a force of those), not \"" +
                           contact.normal_text + "\"");
    found = &contact;
  }
  return found;
}

Scene sliding_scene(const Scene& scene, const SceneContact& contact) {
  if (scene.source_text().empty())
    throw InputError(contact.on_slip_where, "contact '" + contact.name + "': the sliding model is derived from the scene's text");
  const JetSpace& jet = *scene.jet;
  // docs/contacts.md, eq. (8): Q_i = -mu F_n sum_k f^k df^k/dq_i' / |f|, |f| as sqrt(f.f + 1e-14):
  // at the slip f = 0, where the model's expanded f.f rounds to about 1e-16 |q'|^2 of either sign;
  // the sliding phase ends at |f| = 1e-6 (below), where the 1e-14 changes the force by 0.5 %.
  GiNaC::ex squares = 0;
  for (int k : contact.rolling) squares += GiNaC::pow(scene.constraints[static_cast<std::size_t>(k)], 2);
  std::map<std::string, std::string> forces;
  for (int i = 0; i < jet.coordinate_count(); ++i) {
    GiNaC::ex q = 0;
    const GiNaC::symbol& v = GiNaC::ex_to<GiNaC::symbol>(jet.q(i, 1));
    for (int k : contact.rolling) {
      const GiNaC::ex f = expand_intermediates(scene.constraints[static_cast<std::size_t>(k)]);
      q += f * f.diff(v);
    }
    if (q.is_zero()) continue;
    const std::string size = "sqrt(" + printed(squares) + " + 1e-14)";
    forces[jet.coordinates()[static_cast<std::size_t>(i)]] =
        "-(" + runtime::number_text(contact.mu, 17) + ")*(" + contact.normal_text + ")*(" + printed(q) + ")/" + size;
  }
  const std::set<int> removed(contact.rolling.begin(), contact.rolling.end());
  return parse_scene(switched_source(scene.source_text(), removed, forces), scene.source_path);
}

std::vector<runtime::Sample> rolling_samples(const std::vector<runtime::Sample>& samples,
                                             const std::vector<SlidingSpan>& sliding) {
  std::vector<runtime::Sample> rolling;
  for (const runtime::Sample& s : samples) {
    bool rolls = true;
    for (const SlidingSpan& span : sliding)
      rolls = rolls && !((s.t > span.from || (span.from_included && s.t == span.from)) && s.t <= span.to);
    if (rolls) rolling.push_back(s);
  }
  return rolling;
}

jit::LoadedModel build_sliding_model(const Scene& scene, const SceneContact& contact, ModelKind kind,
                                     const jit::BuildOptions& options) {
  return jit::build(sliding_scene(scene, contact), kind, options);
}

SwitchedRun simulate_switched(const Scene& scene, const SceneContact& contact, const runtime::Model& rolling,
                              const runtime::Model& sliding, const std::vector<double>& p,
                              const runtime::InitialState& initial, const std::vector<double>& times,
                              const runtime::IntegratorOptions& options, const std::vector<SceneEvent>& events,
                              const runtime::InputFunction& inputs) {
  SwitchedRun out;
  std::vector<double> ps(static_cast<std::size_t>(sliding.n_parameters()));
  const std::vector<double> sliding_defaults = sliding.default_parameters();
  for (int j = 0; j < sliding.n_parameters(); ++j) {
    // The rolling model's value, else the scene's (a parameter only the Coulomb force reads,
    // a mu = "muT" or a normal force's): the sliding model's defaults are the text's.
    const std::string name = sliding.table().parameter_names[j];
    const int i = rolling.parameter_index(name);
    const std::optional<int> k = scene.jet->parameter_index(name);
    ps[static_cast<std::size_t>(j)] = i >= 0 ? p.at(static_cast<std::size_t>(i))
                                      : k     ? scene.parameter_values.at(static_cast<std::size_t>(*k))
                                              : sliding_defaults[static_cast<std::size_t>(j)];
  }
  const Layout layout = layout_of(contact, rolling, sliding);
  const std::size_t nk = contact.rolling.size();
  // F_n and the slip velocity f on either model's samples.
  SampleExpressions on_rolling(scene, rolling, p), on_sliding(scene, sliding, ps);
  for (SampleExpressions* e : {&on_rolling, &on_sliding}) {
    e->add(contact.normal);
    for (int k : contact.rolling) e->add(scene.constraints[static_cast<std::size_t>(k)]);
  }
  const auto to_rolling = [&](const runtime::Sample& s) {
    if (s.y.size() != static_cast<std::size_t>(sliding.n_states())) return runtime::Sample{s.t, {}, {}, s.u};  // none
    const std::vector<double> v = on_sliding.evaluate(s);
    double speed = 0;
    for (std::size_t k = 0; k < nk; ++k) speed += v[1 + k] * v[1 + k];
    speed = std::sqrt(speed);
    runtime::Sample r;
    r.t = s.t;
    r.u = s.u;
    for (std::size_t i = 0; i < layout.from.size(); ++i) {
      if (layout.from[i] >= 0) {
        r.y.push_back(s.y[static_cast<std::size_t>(layout.from[i])]);
        r.yp.push_back(s.yp.empty() ? 0.0 : s.yp[static_cast<std::size_t>(layout.from[i])]);
      } else if (layout.friction[i] >= 0) {  // the Coulomb force's component: -mu F_n f_k/|f|
        const double fk = v[1 + static_cast<std::size_t>(layout.friction[i])];
        r.y.push_back(speed > 0 ? -contact.mu * v[0] * fk / speed : 0.0);
        r.yp.push_back(0.0);
      } else {
        r.y.push_back(NAN);
        r.yp.push_back(0.0);
      }
    }
    return r;
  };
  const auto sliding_start = [&](const runtime::Sample& r) {
    runtime::InitialState st;
    st.t0 = r.t;
    st.y.assign(static_cast<std::size_t>(sliding.n_states()), 0.0);
    st.yp.assign(static_cast<std::size_t>(sliding.n_states()), 0.0);
    st.given.assign(static_cast<std::size_t>(sliding.n_states()), false);
    for (std::size_t i = 0; i < layout.from.size(); ++i) {
      const int j = layout.from[i];
      if (j < 0) continue;
      st.y[static_cast<std::size_t>(j)] = r.y[i];
      st.yp[static_cast<std::size_t>(j)] = r.yp.empty() ? 0.0 : r.yp[i];
      st.given[static_cast<std::size_t>(j)] = sliding.is_differential(j);
    }
    return st;
  };
  const auto rolling_start = [&](const runtime::Sample& r) {
    runtime::InitialState st;
    st.t0 = r.t;
    st.y = r.y;
    st.yp = r.yp;
    st.given.assign(r.y.size(), false);
    for (int i = 0; i < rolling.n_states(); ++i) st.given[static_cast<std::size_t>(i)] = rolling.is_differential(i);
    st.repair = true;  // q' onto the rolling constraints; the positions stay
    st.pinned.assign(r.y.size(), false);
    for (int c = 0; c < rolling.n_coordinates(); ++c)
      if (const int i = rolling.state_index(c, 0); i >= 0) st.pinned[static_cast<std::size_t>(i)] = true;
    return st;
  };
  const auto start_sample = [](const runtime::InitialState& st) {
    runtime::Sample s;
    s.t = st.t0;
    s.y = st.y;
    s.yp = st.yp.empty() ? std::vector<double>(st.y.size(), 0.0) : st.yp;
    return s;
  };
  const auto slip_velocity = [&](const SampleExpressions& e, const runtime::Sample& s) {
    const std::vector<double> v = e.evaluate(s);
    return std::vector<double>(v.begin() + 1, v.end());
  };

  std::vector<runtime::Event> rolling_events = runtime_events(events, scene, rolling, p);
  for (runtime::Event& e : runtime_events({slip_event(scene, contact)}, scene, rolling, p)) rolling_events.push_back(e);
  std::vector<SceneEvent> plain;  // the events the sliding model evaluates: those without multipliers
  for (const SceneEvent& e : events)
    if (!uses_multiplier(scene, e.expression)) plain.push_back(e);
  std::set<std::string> stops;
  for (const SceneEvent& e : events)
    if (e.action == EventAction::stop) stops.insert(e.name);
  const std::string slip_name = contact.name + ".slip", stick_name = contact.name + ".stick";

  // Does the run start sliding? (the initial values violate the rolling constraints)
  runtime::Sample at;
  at.t = initial.t0;
  at.y = initial.y;
  at.yp = initial.yp.empty() ? std::vector<double>(initial.y.size(), 0.0) : initial.yp;
  bool sliding_now = false;
  std::vector<double> direction;
  {
    const std::vector<double> f = slip_velocity(on_rolling, at);
    double speed = 0;
    for (double x : f) speed += x * x;
    speed = std::sqrt(speed);
    if (speed > 1e-9) {
      sliding_now = true;
      for (double x : f) direction.push_back(x / speed);
    }
  }
  runtime::InitialState start = sliding_now ? sliding_start(at) : initial;
  double t = initial.t0;
  bool first = true;
  SlidingSpan span{t, 0, true};  // the run starts sliding: [t0, ...
  for (int switches = 0;; ++switches) {
    std::vector<double> phase_times;
    for (double x : times)
      if (first ? x >= t : x > t) phase_times.push_back(x);
    if (phase_times.empty()) break;
    runtime::RunResult phase;
    if (!sliding_now) {
      phase = runtime::simulate(rolling, p, start, phase_times, options, rolling_events, inputs);
      if (!first) {  // report the projection onto the rolling constraints at the stick
        double moved = 0;
        for (std::size_t i = 0; i < start.y.size(); ++i)
          if (start.given[i] && std::isfinite(start.y[i])) moved = std::max(moved, std::abs(phase.initial.y[i] - start.y[i]));
        out.notes.push_back("note: contact " + contact.name + " rolls again at t = " + runtime::number_text(t, 12) +
                            ": q' projected onto its rolling constraints (largest change " + runtime::number_text(moved, 3) +
                            ")");
      }
    } else {
      std::vector<runtime::Event> sliding_events = runtime_events(plain, scene, sliding, ps);
      runtime::Event stick;
      stick.name = stick_name;
      stick.terminal = true;
      stick.direction = -1;  // the slip velocity along its direction at the slip falls through zero
      const int n = sliding.n_states();
      // The Coulomb force's Jacobian grows as 1/|f|: IDA's corrector stops converging a little
      // before f = 0. The event fires at the slip speed `near` and the stick itself is found by
      // following the state's derivative the remaining O(near) time (below; docs/contacts.md).
      double size0 = 0;
      for (double x : slip_velocity(on_sliding, start_sample(start))) size0 = std::max(size0, std::abs(x));
      const double near = 1e-6 * std::max(1.0, size0);
      stick.function = [&on_sliding, direction, n, near](double tt, const double* y, const double* yp) {
        runtime::Sample s;
        s.t = tt;
        s.y.assign(y, y + n);
        s.yp.assign(yp, yp + n);
        const std::vector<double> v = on_sliding.evaluate(s);
        double along = 0;
        for (std::size_t k = 0; k < direction.size(); ++k) along += v[1 + k] * direction[k];
        return along - near;
      };
      sliding_events.push_back(stick);
      // |f| of the Coulomb force is a singular set of the sliding model, met at each stick: the
      // stick event ends the phase there, not the singularity monitor.
      runtime::IntegratorOptions sliding_options = options;
      sliding_options.singularity_threshold = -1;  // |s_k| + |s_k(t0)| > 0: no monitor stops the phase
      phase = runtime::simulate(sliding, ps, start, phase_times, sliding_options, sliding_events, inputs);
      for (runtime::Sample& s : phase.samples) s = to_rolling(s);
      phase.initial = to_rolling(phase.initial);
      for (runtime::EventHit& hit : phase.events) {
        runtime::Sample s;
        s.t = hit.t;
        s.y = hit.y;
        s.yp = hit.yp;
        if (hit.name == stick_name) {  // on to f.d = 0 along y' (the rest of the step is O(near^2))
          const auto along = [&](const runtime::Sample& at) {
            const std::vector<double> f = slip_velocity(on_sliding, at);
            double a = 0;
            for (std::size_t k = 0; k < direction.size(); ++k) a += f[k] * direction[k];
            return a;
          };
          const double h = 1e-6;
          runtime::Sample ahead = s;
          for (std::size_t i = 0; i < ahead.y.size(); ++i) ahead.y[i] += h * s.yp[i];
          const double g0 = along(s), slope = (along(ahead) - g0) / h;
          const double tau = slope < 0 ? -g0 / slope : 0.0;
          for (std::size_t i = 0; i < s.y.size(); ++i) s.y[i] += tau * s.yp[i];
          s.t += tau;
          hit.t = s.t;
        }
        const runtime::Sample r = to_rolling(s);
        hit.y = r.y;
        hit.yp = r.yp;
      }
    }
    if (first) out.run.initial = phase.initial;
    out.run.samples.insert(out.run.samples.end(), phase.samples.begin(), phase.samples.end());
    out.run.events.insert(out.run.events.end(), phase.events.begin(), phase.events.end());
    runtime::Statistics& st = out.run.statistics;
    st.steps += phase.statistics.steps;
    st.residual_evaluations += phase.statistics.residual_evaluations;
    st.jacobian_evaluations += phase.statistics.jacobian_evaluations;
    st.linear_solver_setups += phase.statistics.linear_solver_setups;
    st.error_test_failures += phase.statistics.error_test_failures;
    st.nonlinear_iterations += phase.statistics.nonlinear_iterations;
    st.nonlinear_failures += phase.statistics.nonlinear_failures;
    st.root_evaluations += phase.statistics.root_evaluations;
    st.projections += phase.statistics.projections;
    st.initialization_seconds += phase.statistics.initialization_seconds;
    st.integration_seconds += phase.statistics.integration_seconds;
    st.linear_solver = phase.statistics.linear_solver;
    st.jacobian = phase.statistics.jacobian;
    if (phase.failure) {
      out.run.failure = phase.failure;
      break;
    }
    bool stopped = false, switched = false;
    for (const runtime::EventHit& hit : phase.events) {
      stopped = stopped || stops.count(hit.name) > 0;
      switched = switched || hit.name == (sliding_now ? stick_name : slip_name);
    }
    if (stopped || !switched || out.run.samples.empty()) break;
    if (switches >= 1000) {
      out.run.failure = runtime::SolverError(runtime::FailureKind::other, t,
                                             "contact " + contact.name + " switched 1000 times between rolling and sliding by t = " +
                                                 runtime::number_text(t, 12));
      break;
    }
    const runtime::EventHit& hit = phase.events.back();
    runtime::Sample r;
    r.t = hit.t;
    r.y = hit.y;
    r.yp = hit.yp;
    if (sliding_now) {
      span.to = hit.t;
      out.sliding.push_back(span);
      start = rolling_start(r);
    } else {
      // The slip velocity develops against the friction force the rolling needed: f ~ -F_t.
      direction.clear();
      double size = 0;
      std::vector<double> force;
      for (int k : contact.rolling) {
        const int i = rolling.state_index(rolling.n_coordinates() + k, 0);
        force.push_back(i >= 0 ? r.y[static_cast<std::size_t>(i)] : 0.0);
        size += force.back() * force.back();
      }
      size = std::sqrt(size);
      for (double x : force) direction.push_back(size > 0 ? -x / size : 0.0);
      start = sliding_start(r);
      span = {hit.t, 0, false};
    }
    sliding_now = !sliding_now;
    t = hit.t;
    first = false;
  }
  if (sliding_now) {
    span.to = INFINITY;
    out.sliding.push_back(span);
  }
  return out;
}

}  // namespace nhc::app
