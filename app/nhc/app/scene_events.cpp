#include "nhc/app/scene_events.hpp"

#include <cmath>
#include <filesystem>
#include <memory>

#include "nhc/app/sample_expressions.hpp"
#include "nhc/errors.hpp"
#include "nhc/base/number_text.hpp"
#include "nhc/scene/expression_parser.hpp"

namespace nhc::app {

SceneEvent stop_when_event(const Scene& scene, const std::string& text, const std::string& field) {
  ExpressionRules rules;
  rules.allow_multipliers = true;  // as [outputs] and [events]
  SceneEvent event;
  event.name = kStopWhenEvent;
  event.text = text;
  event.where = {field, 0, 0};
  try {
    event.expression = parse_expression(text, *scene.jet, rules);
  } catch (const ExpressionSyntaxError& error) {
    throw InputError(event.where, "in " + field + " \"" + text + "\" at character " +
                                      std::to_string(error.offset() + 1) + ": " + error.what());
  }
  event.direction = EventDirection::any;
  event.action = EventAction::stop;
  return event;
}

std::vector<runtime::Event> runtime_events(const std::vector<SceneEvent>& events, const Scene& scene,
                                           const runtime::Model& model, const std::vector<double>& p) {
  std::vector<runtime::Event> out;
  for (const SceneEvent& event : events) {
    for (int k = 0; k < static_cast<int>(scene.jet->inputs().size()); ++k)
      if (event.expression.has(scene.jet->input(k)))
        throw InputError(event.where, "event '" + event.name + "' uses the input " +
                                          scene.jet->inputs()[static_cast<std::size_t>(k)] +
                                          ": events are functions of t and the state");
    // One program per event: the root function is called with y and y' only.
    auto expression = std::make_shared<SampleExpressions>(scene, model, p);
    if (const std::string missing = expression->add(event.expression); !missing.empty())
      throw InputError(event.where, "event '" + event.name + "' uses " + missing + ", which the " + model.model_name() +
                                        " model does not compute");
    expression->prepare();  // here, under the caller's symbolic lock, not in the run
    const int n = model.n_states();
    auto sample = std::make_shared<runtime::Sample>();
    runtime::Event e;
    e.name = event.name;
    e.terminal = event.action == EventAction::stop;
    e.met_below_at_start = event.met_below_at_start;
    e.direction = event.direction == EventDirection::up ? 1 : event.direction == EventDirection::down ? -1 : 0;
    // A value that is not a finite number is no crossing: a SolverError naming the event, its
    // expression and t, which the integrator takes as the event's failure there (it locates the
    // first instant it fails by bisection, and reports the error met there; docs/events.md).
    e.function = [expression, sample, n, name = event.name, text = event.text](double t, const double* y,
                                                                               const double* yp) {
      sample->t = t;
      sample->y.assign(y, y + n);
      sample->yp.assign(yp, yp + n);
      const double v = expression->evaluate(*sample).front();
      if (!std::isfinite(v))
        throw base::SolverError(base::FailureKind::other, t,
                                "event " + name + " (\"" + text + "\") is " + (std::isnan(v) ? "NaN" : "infinite") +
                                    " at t = " + base::number_text(t, 15) +
                                    ": its crossings cannot be told there (an event must be a finite number "
                                    "along the motion)");
      return v;
    };
    out.push_back(std::move(e));
  }
  return out;
}

std::string event_line(const runtime::EventHit& hit) {
  return "event " + hit.name + " at t = " + base::number_text(hit.t, 12);
}

std::string events_csv_path(const std::string& csv_path) {
  std::filesystem::path path(csv_path);
  path.replace_extension();
  return path.string() + ".events.csv";
}

void write_events_csv(std::ostream& out, const std::vector<runtime::EventHit>& hits) {
  out << "name,t\n";
  for (const runtime::EventHit& hit : hits) out << hit.name << "," << base::shortest_text(hit.t) << "\n";
}

}  // namespace nhc::app
