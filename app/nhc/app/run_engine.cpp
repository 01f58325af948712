#include "nhc/app/run_engine.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "nhc/app/contact_forces.hpp"
#include "nhc/app/integrate.hpp"
#include "nhc/app/law_input_values.hpp"
#include "nhc/app/scene_events.hpp"
#include "nhc/errors.hpp"
#include "nhc/io/output_path.hpp"
#include "nhc/base/number_text.hpp"
#include "nhc/long_work.hpp"

namespace nhc::app {

namespace {

[[noreturn]] void refuse(const std::string& field, const std::string& message) {
  throw InputError({field, 0, 0}, message);
}

void add_statistics(runtime::Statistics& total, const runtime::Statistics& phase) {
  total.steps += phase.steps;
  total.residual_evaluations += phase.residual_evaluations;
  total.jacobian_evaluations += phase.jacobian_evaluations;
  total.linear_solver_setups += phase.linear_solver_setups;
  total.error_test_failures += phase.error_test_failures;
  total.nonlinear_iterations += phase.nonlinear_iterations;
  total.nonlinear_failures += phase.nonlinear_failures;
  total.root_evaluations += phase.root_evaluations;
  total.projections += phase.projections;
  total.initialization_seconds += phase.initialization_seconds;
  total.integration_seconds += phase.integration_seconds;
  total.linear_solver = phase.linear_solver;
  total.jacobian = phase.jacobian;
}

/// Takes the symbolic lock `section` again when destroyed, unless it is held: declared after the
/// run's symbolic objects, it is destroyed before them, also when an exception passes.
struct Relock {
  std::optional<SymbolicSection>& section;
  ~Relock() {
    if (!section) section.emplace();
  }
};

}  // namespace

void check_run_features(const Scene& scene, const RunFeatures& f, const FieldNames& names) {
  if (f.sensitivities && f.variational)
    refuse(names.sensitivity, names.sensitivity + " integrates with IDAS; it does not go with " + names.variational);
  if (f.sensitivities && (!f.replaced_inputs.empty() || f.inputs_function))
    refuse(names.sensitivity, names.sensitivity + " follows the scene's default input signals: it does not go with " +
                                  names.inputs +
                                  " (the derivative of a replaced input by the parameters is not known)");
  if (f.controller) {
    const std::string controller = f.controller_name + " (" + f.controller_where + ")";
    if (f.sensitivities) refuse(names.sensitivity, names.sensitivity + ": " + controller + " is not differentiated");
    const std::string rows =
        ": " + f.controller_name + " runs from sample to sample, whose times are the rows (" + f.controller_where + ")";
    if (f.outputs) refuse(names.outputs, names.outputs + rows);
    if (f.output_times) refuse(names.output_times, names.output_times + rows);
    if (f.variational)
      refuse(names.variational,
             names.variational + ": " + controller +
                 " restarts IDA at each sample; the variational integrator takes fixed steps of its own");
    for (const std::string& name : f.replaced_inputs)
      if (f.controls_all_inputs ||
          std::find(f.controlled_inputs.begin(), f.controlled_inputs.end(), name) != f.controlled_inputs.end())
        refuse(names.inputs,
               names.inputs + " " + name + ": " + f.controller_name + " sets it (" + f.controller_where + ")");
    if (f.mpc && !scene.contacts.empty())
      throw InputError(
          scene.contacts[0].where,
          "contact '" + scene.contacts[0].name + "': " + controller +
              " plans with the equations of [optimize], which hold no contact force, so its plans cannot keep the "
              "contact from slipping; a controller of laws or a function controller runs with contacts");
    if (f.inputs_function && f.controls_all_inputs)
      refuse(names.inputs, names.inputs + ": " + f.controller_name + " sets every input (" + f.controller_where + ")");
  }
  if (f.variational) {
    const std::string why = " takes fixed steps and locates no events; ";
    if (!scene.events.empty())
      refuse(names.variational, names.variational + why + "the scene's event '" + scene.events[0].name + "' (" +
                                    scene.events[0].where.str() + ") needs IDA");
    if (!scene.contacts.empty())
      refuse(names.variational, names.variational + why + "contact '" + scene.contacts[0].name + "' (" +
                                    scene.contacts[0].where.str() + ") needs IDA to locate its slip");
  }
  if (f.sensitivities) {
    const std::string why =
        ", which the run with sensitivities does not locate (IDAS runs on to t_end; the derivative "
        "of a switching time is not computed)";
    for (const SceneEvent& e : scene.events)
      if (e.action == EventAction::stop)
        refuse(names.sensitivity,
               names.sensitivity + ": event '" + e.name + "' (" + e.where.str() + ") ends the run" + why);
    if (!scene.contacts.empty())
      refuse(names.sensitivity, names.sensitivity + ": contact '" + scene.contacts[0].name + "' (" +
                                    scene.contacts[0].where.str() + ") may slip, an event" + why);
  }
}

RunOutcome simulate(const RunPlan& plan) {
  // The symbolic work of the run (its events' and contact's expressions made and lowered, the
  // [inputs] laws evaluated on the rows, all of them released) holds the symbolic lock
  // (nhc/long_work.hpp); the integration runs without it, so that front ends may run engines on
  // several threads at once (nhc ensemble's workers, Python's threads). Declared first: destroyed
  // last, after the run's symbolic objects, which are released under it.
  std::optional<SymbolicSection> symbolic;
  symbolic.emplace();
  RunOutcome out;
  const Scene& scene = *plan.scene;
  const runtime::Model& rolling = *plan.model;
  const std::vector<double>& p = plan.p;
  if (plan.request.variational) {  // check_run_features refused events, contacts and a controller
    symbolic.reset();
    IntegratedRun run = integrate(plan.request, rolling, p, plan.initial, plan.times, plan.options, {}, plan.inputs);
    symbolic.emplace();
    out.run = std::move(run.run);
    out.max_discrete_constraint = run.max_discrete_constraint;
    record_law_inputs(scene, rolling, p, out.run.samples);
    out.drift_samples = out.run.samples;
    return out;
  }

  // The contact that slides, side by side with its sliding model.
  const SceneContact* slide = sliding_contact(scene);
  out.slide = slide;
  std::optional<ContactSwitch> contact;
  if (slide) {
    if (!plan.sliding_model)
      throw std::logic_error("run engine: the sliding model of contact " + slide->name + " is missing");
    contact.emplace(scene, *slide, rolling, *plan.sliding_model, p);
  }
  const RunControl* control = plan.control ? &*plan.control : nullptr;
  runtime::IntegratorOptions options = plan.options;
  if (control) options.progress = nullptr;  // one integration per sample: a bar would restart at every one

  // The events of either model: the run's, the slip of the sliding contact (rolling), its stick
  // (sliding, made at each slip: it follows the slip's direction).
  std::vector<runtime::Event> rolling_events = runtime_events(plan.events, scene, rolling, p);
  std::vector<runtime::Event> sliding_events;
  std::string slip_name, stick_name;
  if (contact) {
    for (runtime::Event& e : runtime_events({slip_event(scene, *slide)}, scene, rolling, p))
      rolling_events.push_back(e);
    sliding_events = runtime_events(events_without_multipliers(scene, plan.events), scene, contact->sliding(),
                                    contact->sliding_parameters());
    slip_name = slide->name + ".slip";
    stick_name = slide->name + ".stick";
  }
  std::set<std::string> stops;
  for (const SceneEvent& e : plan.events)
    if (e.action == EventAction::stop) stops.insert(e.name);
  symbolic.reset();  // the run: numeric work (an expression GiNaC must evaluate takes the lock itself)
  const Relock relock{symbolic};

  // The inputs: those from outside (or the default signals), the controller's held ones over them.
  const int n_inputs = rolling.n_inputs();
  const int n_parameters = rolling.n_parameters();
  auto rolling_defaults = std::make_shared<runtime::InputValues>(rolling, p);
  const runtime::InputFunction rolling_free =
      plan.inputs
          ? plan.inputs
          : runtime::InputFunction([rolling_defaults, n_parameters, n_inputs](double t, const double* y, double* u) {
              const double* values = rolling_defaults->at(t, y);
              std::copy(values + n_parameters, values + n_parameters + n_inputs, u);
            });
  runtime::InputFunction sliding_free;
  if (contact) {
    const runtime::Model& sliding = contact->sliding();
    if (plan.inputs) {  // u(t, y) of the rolling model's states: read them off the sliding model's
      const ContactSwitch* c = &*contact;
      sliding_free = [c, f = plan.inputs, n_inputs](double t, const double* y, double* u) {
        std::vector<double> yr, ur(static_cast<std::size_t>(n_inputs), 0.0);
        c->rolling_states(y, yr);
        f(t, yr.data(), ur.data());
        const std::vector<double> us = c->sliding_inputs(ur);
        std::copy(us.begin(), us.end(), u);
      };
    } else {
      auto defaults = std::make_shared<runtime::InputValues>(sliding, contact->sliding_parameters());
      sliding_free = [defaults, np = sliding.n_parameters(), ni = sliding.n_inputs()](double t, const double* y,
                                                                                      double* u) {
        const double* values = defaults->at(t, y);
        std::copy(values + np, values + np + ni, u);
      };
    }
  }
  std::optional<std::vector<double>> held;  // the controller's last inputs (the rolling model's order)
  const bool all_held = control && std::all_of(control->held.begin(), control->held.end(), [](bool h) { return h; });
  const auto apply_inputs = [&](runtime::Integrator& integrator, bool sliding_now) {
    if (!held) {
      if (plan.inputs) integrator.set_inputs(sliding_now ? sliding_free : plan.inputs);
      return;
    }
    std::vector<double> u = sliding_now ? contact->sliding_inputs(*held) : *held;
    if (all_held) {
      integrator.hold_inputs(std::move(u));
      return;
    }
    std::vector<double> mask(control->held.size());
    for (std::size_t i = 0; i < mask.size(); ++i) mask[i] = control->held[i] ? 1.0 : 0.0;
    if (sliding_now) mask = contact->sliding_inputs(mask);
    integrator.set_inputs(
        [u, mask, free = sliding_now ? sliding_free : rolling_free](double t, const double* y, double* values) {
          free(t, y, values);
          for (std::size_t i = 0; i < mask.size(); ++i)
            if (mask[i] != 0) values[i] = u[i];
        });
  };

  // Where the run starts: a sliding contact slides from t0 only when the rolling model cannot
  // start from the given values. Its consistent point keeps them and solves the others (the
  // values nhc analyze reports); given values that miss the rolling constraints start it sliding
  // from them.
  runtime::InitialState start = plan.initial;
  bool sliding_now = false;
  std::vector<double> direction;
  if (contact) {
    const double t0 = plan.initial.t0;
    runtime::Sample at{t0,
                       plan.initial.y,
                       plan.initial.yp.empty() ? std::vector<double>(plan.initial.y.size(), 0.0) : plan.initial.yp,
                       {}};
    std::vector<double> solved = plan.initial.y;
    try {
      runtime::InputValues values(rolling, p);
      if (plan.inputs) values.set_function(plan.inputs);
      const std::vector<double> scale = runtime::initial_repair_scale(plan.initial);
      runtime::solve_starting_point(rolling, values.at(t0, solved.data()), t0, solved.data(), plan.initial.given,
                                    options.rtol, options.atol, plan.initial.repair ? &scale : nullptr);
      at.y = solved;
    } catch (const base::SolverError&) {
      // the given values miss the rolling constraints: they are the sliding model's start
    }
    const std::vector<double> f = contact->slip_on_rolling(at);
    double speed = 0;
    for (double x : f) speed += x * x;
    speed = std::sqrt(speed);
    if (speed > 1e-9) {
      sliding_now = true;
      for (double x : f) direction.push_back(x / speed);
      start = contact->sliding_start(at);
    }
  }

  const std::vector<double>& times = control ? control->samples : plan.times;
  const auto push_row = [&](runtime::Sample row, const std::vector<double>* z, bool at_sample) {
    if (!out.run.samples.empty() && !(row.t > out.run.samples.back().t)) return;
    out.run.samples.push_back(std::move(row));
    if (control && control->scene_laws) out.controller_rows.push_back(z ? *z : control->scene_laws->state());
    else if (control && control->columns) out.controller_rows.push_back(control->columns(at_sample));
  };
  std::size_t next_sample = 0;  // under a controller: the sample to reach next
  double t = plan.initial.t0;
  bool first = true;
  SlidingSpan span{t, 0, true};  // the run starts sliding: [t0, ...
  for (int switches = 0;; ++switches) {
    const runtime::Model& model = sliding_now ? contact->sliding() : rolling;
    const auto to_run = [&](const runtime::Sample& s) { return sliding_now ? contact->to_rolling(s) : s; };
    runtime::IntegratorOptions phase_options = options;
    // |f| of the Coulomb force is a singular set of the sliding model, met at each stick: the
    // stick event ends the phase there, not the singularity monitor.
    if (sliding_now) phase_options.singularity_threshold = -1;
    runtime::Integrator integrator(model, sliding_now ? contact->sliding_parameters() : p, phase_options);
    std::vector<runtime::Event> phase_events = sliding_now ? sliding_events : rolling_events;
    if (sliding_now) phase_events.push_back(contact->stick_event(direction, start));
    for (const runtime::Event& e : phase_events) integrator.add_event(e);
    apply_inputs(integrator, sliding_now);  // before initialize(): the inputs it starts with

    std::size_t hits_seen = 0;
    bool stopped = false;
    std::optional<runtime::EventHit> switch_hit;
    // One event met (the phase model's states), in the rolling model's.
    const auto take_hit = [&](runtime::EventHit hit) {
      if (sliding_now && hit.name == stick_name) contact->carry_to_stick(hit, direction);
      if (sliding_now) {
        const runtime::Sample r = contact->to_rolling(runtime::Sample{hit.t, hit.y, hit.yp, {}});
        hit.y = r.y;
        hit.yp = r.yp;
      }
      out.run.events.push_back(hit);
      stopped = stopped || stops.count(hit.name) > 0;
      if (contact && hit.name == (sliding_now ? stick_name : slip_name)) switch_hit = hit;
    };
    // The events met since the last look.
    const auto take_hits = [&] {
      const std::vector<runtime::EventHit>& hits = integrator.events();
      for (; hits_seen < hits.size(); ++hits_seen) take_hit(hits[hits_seen]);
    };
    // The held inputs change at a sample: an event function that jumps across zero there (in its
    // direction) is met at the sample, which IDA's root finding, restarted there, cannot see.
    const auto crossed_at_sample = [&](const runtime::Sample& before, const runtime::Sample& after) {
      for (const runtime::Event& e : phase_events) {
        const double a = e.function(before.t, before.y.data(), before.yp.data());
        const double b = e.function(after.t, after.y.data(), after.yp.data());
        const bool up = a < 0 && b >= 0, down = a > 0 && b <= 0;
        if ((e.direction > 0 && up) || (e.direction < 0 && down) || (e.direction == 0 && (up || down)))
          take_hit(runtime::EventHit{e.name, after.t, after.y, after.yp});
      }
    };
    // A sample of the controller at the point `reached` (the rolling model's states): its inputs
    // held from there on, the row the point after the restart.
    const auto sample = [&](const runtime::Sample& reached_here, double tk, std::size_t k) {
      const runtime::Sample reached = to_run(reached_here);
      std::vector<double> u = control->law(reached);
      ++out.controller_calls;
      if (static_cast<int>(u.size()) != n_inputs)
        throw std::invalid_argument("the controller returned " + std::to_string(u.size()) + " inputs; the model has " +
                                    std::to_string(n_inputs));
      for (int i = 0; i < n_inputs; ++i)
        if ((all_held || control->held[static_cast<std::size_t>(i)]) && !std::isfinite(u[static_cast<std::size_t>(i)]))
          throw base::SolverError(base::FailureKind::nonfinite_residual, tk,
                                  "the controller's input " + rolling.input_name(i) + " is " +
                                      base::shortest_text(u[static_cast<std::size_t>(i)]) +
                                      " at t = " + base::shortest_text(tk) + " (sample " + std::to_string(k) + ")");
      held = std::move(u);
      apply_inputs(integrator, sliding_now);  // the restart keeps the states, recomputes y' and the algebraic ones
      runtime::Sample after = integrator.point();
      after.t = tk;
      if (k > 0) crossed_at_sample(reached_here, after);
      push_row(to_run(after), control->scene_laws ? &control->scene_laws->state_history().back() : nullptr, true);
    };

    try {
      const runtime::Sample initial_point = integrator.initialize(start, runtime::first_output_after(times, t));
      if (first) out.run.initial = to_run(initial_point);
      if (!first && !sliding_now) {  // report the projection onto the rolling constraints at the stick
        double moved = 0;
        for (std::size_t i = 0; i < start.y.size(); ++i)
          if (start.given[i] && std::isfinite(start.y[i]))
            moved = std::max(moved, std::abs(initial_point.y[i] - start.y[i]));
        out.notes.push_back("note: contact " + slide->name + " rolls again at t = " + base::number_text(t, 12) +
                            ": q' projected onto its rolling constraints (largest change " +
                            base::number_text(moved, 3) + ")");
      }
      if (control) {
        if (next_sample == 0) {
          sample(integrator.point(), times[0], 0);
          next_sample = 1;
        }
        while (next_sample < times.size() && !stopped && !switch_hit) {
          const double tk = times[next_sample];
          std::optional<runtime::Sample> reached;
          integrator.integrate({tk}, [&](const runtime::Sample& s) { reached = s; });
          take_hits();
          if (stopped || switch_hit) {
            // The point the event ended the run at is its last row; a switch goes on to the sample.
            if (stopped && reached) push_row(to_run(*reached), nullptr, false);
            break;
          }
          runtime::Sample at = *reached;
          at.t = tk;  // IDA stops there exactly (its stop time)
          sample(at, tk, next_sample);
          ++next_sample;
        }
      } else {
        std::vector<double> phase_times;
        for (double x : times)
          if (first ? x >= t : x > t) phase_times.push_back(x);
        if (!phase_times.empty())
          integrator.integrate(phase_times, [&](const runtime::Sample& s) { push_row(to_run(s), nullptr, false); });
        take_hits();
      }
    } catch (const base::SolverError& e) {
      take_hits();
      add_statistics(out.run.statistics, integrator.statistics());
      out.run.failure = e;
      break;
    }
    add_statistics(out.run.statistics, integrator.statistics());
    if (stopped || !switch_hit || out.run.samples.empty()) break;
    if (switches >= 1000) {
      out.run.failure = base::SolverError(base::FailureKind::other, t,
                                          "contact " + slide->name +
                                              " switched 1000 times between rolling and "
                                              "sliding by t = " +
                                              base::number_text(t, 12));
      break;
    }
    const runtime::Sample r{switch_hit->t, switch_hit->y, switch_hit->yp, {}};
    if (sliding_now) {
      span.to = r.t;
      out.sliding.push_back(span);
      start = contact->rolling_start(r);
    } else {
      direction = contact->slip_direction(r);
      start = contact->sliding_start(r);
      span = {r.t, 0, false};
    }
    sliding_now = !sliding_now;
    t = r.t;
    first = false;
  }
  if (sliding_now) {
    span.to = INFINITY;
    out.sliding.push_back(span);
  }

  symbolic.emplace();
  record_law_inputs(scene, rolling, p, out.run.samples);  // what the [inputs] laws applied
  if (out.sliding.empty()) {
    out.drift_samples = out.run.samples;
  } else {
    out.drift_samples = rolling_samples(out.run.samples, out.sliding);
    out.notes.push_back("the drift above is measured over the samples where contact " + slide->name + " rolls (" +
                        std::to_string(out.drift_samples.size()) + " of " + std::to_string(out.run.samples.size()) +
                        ")");
  }
  return out;
}

runtime::SensitivityRun simulate_sensitivities(const RunPlan& plan,
                                               const std::vector<runtime::SensitivityParameter>& thetas,
                                               const runtime::SensitivityOptions& options) {
  runtime::SensitivityRun run =
      runtime::simulate_sensitivities(*plan.model, plan.p, plan.initial, thetas, plan.times, plan.options, options);
  record_law_inputs(*plan.scene, *plan.model, plan.p, run.samples);  // what the [inputs] laws applied
  return run;
}

std::string side_file_path(const std::string& output, const std::function<std::string(const std::string&)>& side,
                           std::string& note) {
  if (output.empty() || output == "-") return "";
  if (output_target(output).kind == OutputTarget::Kind::stream) {
    note = "note: no file beside " + output + " (" + side(output) +
           "): it is a device or FIFO, written in place, beside which the run writes nothing";
    return "";
  }
  return side(output);
}

}  // namespace nhc::app
