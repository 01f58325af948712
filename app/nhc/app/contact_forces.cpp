#include "nhc/app/contact_forces.hpp"

#include <cmath>

#include "nhc/base/number_text.hpp"

namespace nhc::app {

GiNaC::ex tangential_force(const Scene& scene, const SceneContact& contact) {
  GiNaC::ex sum = 0;
  for (int k : contact.rolling) sum += GiNaC::pow(scene.jet->lambda(k, 0), 2);
  return GiNaC::sqrt(sum);
}

SceneEvent slip_event(const Scene& scene, const SceneContact& contact) {
  SceneEvent event;
  event.name = contact.name + ".slip";
  event.text = "mu*(" + contact.normal_text + ") - |F_t|";
  event.where = contact.where;
  // Friction suffices while |F_t| <= mu F_n (Coulomb); the crossing from above is the slip.
  event.expression = GiNaC::numeric(contact.mu) * contact.normal - tangential_force(scene, contact);
  event.direction = EventDirection::down;
  event.action = EventAction::stop;
  event.met_below_at_start = true;
  return event;
}

namespace {

/// The event NAME.liftoff of a contact: F_n falling through zero, or below zero at t0 (the contact
/// would have to pull); it ends the run (docs/contacts.md, "Lift-off").
SceneEvent liftoff_event(const SceneContact& contact) {
  SceneEvent event;
  event.name = contact.name + ".liftoff";
  event.text = contact.normal_text;
  event.where = contact.where;
  event.expression = contact.normal;  // a contact pushes (F_n > 0); at F_n = 0 it lets go
  event.direction = EventDirection::down;
  event.action = EventAction::stop;
  event.met_below_at_start = true;
  return event;
}

}  // namespace

// Each contact's lift-off, then its slip where on_slip is "stop", in file order: where both are
// met at one instant (at t0 with F_n < 0, or where F_n reaches zero with no tangential force, when
// mu F_n - |F_t| reaches zero with it) the integrator reports the first, the lift-off.
std::vector<SceneEvent> slip_events(const Scene& scene) {
  std::vector<SceneEvent> events;
  for (const SceneContact& contact : scene.contacts) {
    events.push_back(liftoff_event(contact));
    if (contact.on_slip == SlipAction::stop) events.push_back(slip_event(scene, contact));
  }
  return events;
}

ContactForces::ContactForces(const Scene& scene, const runtime::Model& model, const std::vector<double>& p)
    : expressions_(scene, model, p) {
  for (const SceneContact& contact : scene.contacts) {
    const GiNaC::ex tangential = tangential_force(scene, contact);
    std::string missing = expressions_.missing(contact.normal);
    if (missing.empty()) missing = expressions_.missing(tangential);
    if (!missing.empty()) {
      notes_.push_back("note: contact '" + contact.name + "' is left out of the " + model.model_name() +
                       " model's CSV: its forces use " + missing + ", which the model does not compute");
      continue;
    }
    kept_.push_back({&contact, expressions_.size(), {}, false});
    expressions_.add(contact.normal);
    expressions_.add(tangential);
    for (const char* column : {".normal", ".tangential", ".ratio", ".state"}) names_.push_back(contact.name + column);
  }
}

std::vector<double> ContactForces::evaluate(const runtime::Sample& sample) const {
  std::vector<double> out;
  if (kept_.empty()) return out;
  const std::vector<double> values = expressions_.evaluate(sample);
  for (const Kept& k : kept_) {
    const double normal = values[k.normal], tangential = values[k.normal + 1];
    bool rolling = true;
    for (std::size_t s = 0; s < k.sliding.size(); ++s) {
      const auto& [from, to] = k.sliding[s];
      if ((sample.t > from || (s == 0 && k.first_closed && sample.t == from)) && sample.t <= to) rolling = false;
    }
    out.insert(out.end(), {normal, tangential, tangential / normal, rolling ? 1.0 : 0.0});
  }
  return out;
}

void ContactForces::set_sliding(const std::string& name, std::vector<std::pair<double, double>> spans,
                                bool first_closed) {
  for (Kept& k : kept_)
    if (k.contact->name == name) {
      k.sliding = std::move(spans);
      k.first_closed = first_closed;
    }
}

std::optional<std::string> ContactForces::slip_line(const runtime::EventHit& hit) const {
  for (std::size_t i = 0; i < kept_.size(); ++i) {
    const std::string& name = kept_[i].contact->name;
    if (hit.name != name + ".slip" && hit.name != name + ".liftoff") continue;
    runtime::Sample sample;
    sample.t = hit.t;
    sample.y = hit.y;
    sample.yp = hit.yp;
    if (hit.name == name + ".liftoff") {
      const double normal = evaluate(sample)[4 * i];
      std::string line = "contact " + name + " lifts off at t = " + base::number_text(hit.t, 12);
      // Met below zero at the start: the contact would have to pull from the first instant.
      if (normal < 0)
        line += " (its normal force \"" + kept_[i].contact->normal_text + "\" is " + base::number_text(normal, 6) +
                " < 0 there: the contact would have to pull)";
      return line;
    }
    const double ratio = evaluate(sample)[4 * i + 2];
    return "contact " + kept_[i].contact->name + " slips at t = " + base::number_text(hit.t, 12) +
           " (needs mu >= " + base::number_text(ratio, 6) + ")";
  }
  return std::nullopt;
}

std::vector<std::string> ContactForces::need_lines(const std::vector<runtime::Sample>& samples) const {
  std::vector<double> worst(kept_.size(), -1), at(kept_.size(), 0);
  for (const runtime::Sample& sample : samples) {
    const std::vector<double> columns = evaluate(sample);
    for (std::size_t i = 0; i < kept_.size(); ++i)  // where F_n <= 0 the contact lifts off: no ratio
      if (columns[4 * i] > 0 && columns[4 * i + 2] > worst[i]) {
        worst[i] = columns[4 * i + 2];
        at[i] = sample.t;
      }
  }
  std::vector<std::string> lines;
  for (std::size_t i = 0; i < kept_.size(); ++i)
    if (worst[i] >= 0)
      lines.push_back("contact " + kept_[i].contact->name + " needs mu >= " + base::number_text(worst[i], 6) +
                      " (the largest |F_t|/F_n at the output times, at t = " + base::number_text(at[i], 6) +
                      "; mu = " + base::number_text(kept_[i].contact->mu, 6) + ")");
  return lines;
}

}  // namespace nhc::app
