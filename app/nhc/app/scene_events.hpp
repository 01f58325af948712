#pragma once
/// \file scene_events.hpp
/// \brief A scene's [events] (and --stop-when, Python's stop_when) as the integrator's events:
/// each expression evaluated on the model's states (sample_expressions.hpp), its zero crossings
/// located by IDA's root finding; the events a run met, as summary lines and as the event table
/// `<stem>.events.csv` (docs/scenes.md, "[events]").

#include <ostream>
#include <string>
#include <vector>

#include "nhc/runtime/runtime.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::app {

/// The name of the event --stop-when (Python: stop_when=) adds.
inline constexpr const char* kStopWhenEvent = "stop_when";

/// The event `text` (an expression as [events] takes it) stops the run at its first zero
/// crossing in either direction. InputError at `field` for a bad expression.
SceneEvent stop_when_event(const Scene& scene, const std::string& text, const std::string& field);

/// The integrator's events for `events` on `model` with parameters `p`. An event whose expression
/// uses a quantity the model does not compute (a multiplier of the suslov model) or an input is
/// refused (InputError at the expression). The returned functions refer to `scene` and `model`,
/// which must outlive them.
std::vector<runtime::Event> runtime_events(const std::vector<SceneEvent>& events, const Scene& scene,
                                           const runtime::Model& model, const std::vector<double>& p);

/// "event NAME at t = T" (T to 12 significant digits).
std::string event_line(const runtime::EventHit& hit);

/// `<stem>.events.csv` beside the CSV `csv_path` (its extension replaced; appended when none).
std::string events_csv_path(const std::string& csv_path);

/// The event table: a header `name,t`, then one row per event met, t to 17 significant digits.
void write_events_csv(std::ostream& out, const std::vector<runtime::EventHit>& hits);

}  // namespace nhc::app
