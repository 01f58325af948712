#include "nhc/app/switched_run.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "nhc/app/contact_forces.hpp"
#include "nhc/app/parameter_values.hpp"
#include "nhc/app/sample_expressions.hpp"
#include "nhc/app/scene_events.hpp"
#include "nhc/errors.hpp"
#include "nhc/expr/intermediate.hpp"
#include "nhc/base/number_text.hpp"

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

}  // namespace

const SceneContact* sliding_contact(const Scene& scene) {
  const SceneContact* found = nullptr;
  for (const SceneContact& contact : scene.contacts) {
    if (contact.on_slip != SlipAction::slide) continue;
    if (found)
      throw InputError(contact.on_slip_where, "contact '" + contact.name +
                                                  "': one contact of a scene may slide (on_slip = \"slide\"); '" +
                                                  found->name + "' does already");
    if (uses_multiplier(scene, contact.normal) || scene.jet->highest_coordinate_order(contact.normal) > 1)
      throw InputError(contact.on_slip_where,
                       "contact '" + contact.name +
                           "': on_slip = \"slide\" needs the normal force as an expression of t, "
                           "q and q' (the sliding model's Coulomb force is a force of those), not \"" +
                           contact.normal_text + "\"");
    found = &contact;
  }
  return found;
}

std::vector<SceneEvent> events_without_multipliers(const Scene& scene, const std::vector<SceneEvent>& events) {
  std::vector<SceneEvent> plain;
  for (const SceneEvent& e : events)
    if (!uses_multiplier(scene, e.expression)) plain.push_back(e);
  return plain;
}

Scene sliding_scene(const Scene& scene, const SceneContact& contact) {
  if (scene.source_text().empty())
    throw InputError(contact.on_slip_where,
                     "contact '" + contact.name + "': the sliding model is derived from the scene's text");
  const JetSpace& jet = *scene.jet;
  // docs/contacts.md, eq. (8): Q_i = -mu F_n sum_k f^k df^k/dq_i' / |f|, |f| as sqrt(f.f + 1e-14):
  // at the slip f = 0, where the model's expanded f.f rounds to about 1e-16 |q'|^2 of either sign;
  // the sliding phase ends at |f| = 1e-6 (below), where the 1e-14 changes the force by 0.5 %.
  GiNaC::ex squares = 0;
  for (int k : contact.rolling) squares += GiNaC::pow(scene.constraints[static_cast<std::size_t>(k)], 2);
  std::map<std::string, std::string> forces;
  for (int i = 0; i < jet.coordinate_count(); ++i) {
    GiNaC::ex q = 0;
    const GiNaC::symbol& v = jet.symbol({VariableKind::coordinate, i, 1});  // the jet's own, not a temporary's
    for (int k : contact.rolling) {
      const GiNaC::ex f = expand_intermediates(scene.constraints[static_cast<std::size_t>(k)]);
      q += f * f.diff(v);
    }
    if (q.is_zero()) continue;
    const std::string size = "sqrt(" + printed(squares) + " + 1e-14)";
    // mu written through the parameters stays their expression: the sliding model reads them at run
    // time (ContactSwitch's parameters), so one build serves every value (--set, an ensemble).
    const std::string mu =
        contact.mu_expression.empty() ? base::number_text(contact.mu, 17) : contact.mu_expression.text;
    forces[jet.coordinates()[static_cast<std::size_t>(i)]] =
        "-(" + mu + ")*(" + contact.normal_text + ")*(" + printed(q) + ")/" + size;
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

ContactSwitch::ContactSwitch(const Scene& scene, const SceneContact& contact, const runtime::Model& rolling,
                             const runtime::Model& sliding, const std::vector<double>& p)
    : scene_(&scene), contact_(&contact), rolling_(&rolling), sliding_(&sliding) {
  // The rolling model's values by name; a parameter only the Coulomb force reads (g of a normal
  // force m*g: the rolling equations do not use it) takes the run's scene's value, --set included.
  ps_ = model_parameters(sliding, scene);
  for (int j = 0; j < sliding.n_parameters(); ++j)
    if (const int i = rolling.parameter_index(sliding.table().parameter_names[j]); i >= 0)
      ps_[static_cast<std::size_t>(j)] = p.at(static_cast<std::size_t>(i));
  // Where the rolling model's states are found in the sliding model's (by name; the multipliers
  // of the remaining constraints renumbered), or which friction component they are.
  std::map<std::string, int> sliding_states;
  for (int j = 0; j < sliding.n_states(); ++j) sliding_states[sliding.state_name(j)] = j;
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
    from_.push_back(friction < 0 && found != sliding_states.end() ? found->second : -1);
    friction_.push_back(friction);
  }
  for (int j = 0; j < sliding.n_inputs(); ++j) inputs_.push_back(rolling.input_index(sliding.input_name(j)));
  on_rolling_ = std::make_shared<SampleExpressions>(scene, rolling, p);
  on_sliding_ = std::make_shared<SampleExpressions>(scene, sliding, ps_);
  for (SampleExpressions* e : {on_rolling_.get(), on_sliding_.get()}) {
    e->add(contact.normal);
    for (int k : contact.rolling) e->add(scene.constraints[static_cast<std::size_t>(k)]);
  }
}

runtime::Sample ContactSwitch::to_rolling(const runtime::Sample& s) const {
  if (s.y.size() != static_cast<std::size_t>(sliding_->n_states())) return runtime::Sample{s.t, {}, {}, {}};  // none
  const std::vector<double> v = on_sliding_->evaluate(s);
  const std::size_t nk = contact_->rolling.size();
  double speed = 0;
  for (std::size_t k = 0; k < nk; ++k) speed += v[1 + k] * v[1 + k];
  speed = std::sqrt(speed);
  runtime::Sample r;
  r.t = s.t;
  for (std::size_t i = 0; i < from_.size(); ++i) {
    if (from_[i] >= 0) {
      r.y.push_back(s.y[static_cast<std::size_t>(from_[i])]);
      r.yp.push_back(s.yp.empty() ? 0.0 : s.yp[static_cast<std::size_t>(from_[i])]);
    } else if (friction_[i] >= 0) {  // the Coulomb force's component: -mu F_n f_k/|f|
      const double fk = v[1 + static_cast<std::size_t>(friction_[i])];
      r.y.push_back(speed > 0 ? -contact_->mu * v[0] * fk / speed : 0.0);
      r.yp.push_back(0.0);
    } else {
      r.y.push_back(NAN);
      r.yp.push_back(0.0);
    }
  }
  // The inputs in the rolling model's order.
  r.u.assign(static_cast<std::size_t>(rolling_->n_inputs()), NAN);
  for (std::size_t j = 0; j < inputs_.size() && j < s.u.size(); ++j)
    if (inputs_[j] >= 0) r.u[static_cast<std::size_t>(inputs_[j])] = s.u[j];
  return r;
}

void ContactSwitch::rolling_states(const double* sliding_y, std::vector<double>& y) const {
  y.assign(from_.size(), 0.0);
  for (std::size_t i = 0; i < from_.size(); ++i)
    if (from_[i] >= 0) y[i] = sliding_y[from_[i]];
}

std::vector<double> ContactSwitch::sliding_inputs(const std::vector<double>& rolling_u) const {
  std::vector<double> u(inputs_.size(), 0.0);
  for (std::size_t j = 0; j < inputs_.size(); ++j)
    if (inputs_[j] >= 0) u[j] = rolling_u.at(static_cast<std::size_t>(inputs_[j]));
  return u;
}

runtime::InitialState ContactSwitch::sliding_start(const runtime::Sample& r) const {
  const std::size_t n = static_cast<std::size_t>(sliding_->n_states());
  runtime::InitialState st;
  st.t0 = r.t;
  st.y.assign(n, 0.0);
  st.yp.assign(n, 0.0);
  st.given.assign(n, false);
  for (std::size_t i = 0; i < from_.size(); ++i) {
    const int j = from_[i];
    if (j < 0) continue;
    st.y[static_cast<std::size_t>(j)] = r.y[i];
    st.yp[static_cast<std::size_t>(j)] = r.yp.empty() ? 0.0 : r.yp[i];
    st.given[static_cast<std::size_t>(j)] = sliding_->is_differential(j);
  }
  return st;
}

runtime::InitialState ContactSwitch::rolling_start(const runtime::Sample& r) const {
  runtime::InitialState st;
  st.t0 = r.t;
  st.y = r.y;
  st.yp = r.yp;
  st.given.assign(r.y.size(), false);
  for (int i = 0; i < rolling_->n_states(); ++i) st.given[static_cast<std::size_t>(i)] = rolling_->is_differential(i);
  st.repair = true;  // q' onto the rolling constraints; the positions stay
  st.pinned.assign(r.y.size(), false);
  for (int c = 0; c < rolling_->n_coordinates(); ++c)
    if (const int i = rolling_->state_index(c, 0); i >= 0) st.pinned[static_cast<std::size_t>(i)] = true;
  return st;
}

std::vector<double> ContactSwitch::slip_on_rolling(const runtime::Sample& s) const {
  const std::vector<double> v = on_rolling_->evaluate(s);
  return std::vector<double>(v.begin() + 1, v.end());
}

std::vector<double> ContactSwitch::slip_on_sliding(const runtime::Sample& s) const {
  const std::vector<double> v = on_sliding_->evaluate(s);
  return std::vector<double>(v.begin() + 1, v.end());
}

std::vector<double> ContactSwitch::slip_direction(const runtime::Sample& r) const {
  // The slip velocity develops against the friction force the rolling needed: f ~ -F_t.
  std::vector<double> force, direction;
  double size = 0;
  for (int k : contact_->rolling) {
    const int i = rolling_->state_index(rolling_->n_coordinates() + k, 0);
    force.push_back(i >= 0 ? r.y[static_cast<std::size_t>(i)] : 0.0);
    size += force.back() * force.back();
  }
  size = std::sqrt(size);
  for (double x : force) direction.push_back(size > 0 ? -x / size : 0.0);
  return direction;
}

runtime::Event ContactSwitch::stick_event(const std::vector<double>& direction,
                                          const runtime::InitialState& start) const {
  runtime::Event stick;
  stick.name = contact_->name + ".stick";
  stick.terminal = true;
  stick.direction = -1;  // the slip velocity along its direction at the slip falls through zero
  const int n = sliding_->n_states();
  runtime::Sample at;
  at.t = start.t0;
  at.y = start.y;
  at.yp = start.yp.empty() ? std::vector<double>(start.y.size(), 0.0) : start.yp;
  // The Coulomb force's Jacobian grows as 1/|f|: IDA's corrector stops converging a little
  // before f = 0. The event fires at the slip speed `near` and the stick itself is found by
  // following the state's derivative the remaining O(near) time (carry_to_stick; docs/contacts.md).
  double size0 = 0;
  for (double x : slip_on_sliding(at)) size0 = std::max(size0, std::abs(x));
  const double near = 1e-6 * std::max(1.0, size0);
  stick.function = [on_sliding = on_sliding_, direction, n, near](double tt, const double* y, const double* yp) {
    runtime::Sample s;
    s.t = tt;
    s.y.assign(y, y + n);
    s.yp.assign(yp, yp + n);
    const std::vector<double> v = on_sliding->evaluate(s);
    double along = 0;
    for (std::size_t k = 0; k < direction.size(); ++k) along += v[1 + k] * direction[k];
    return along - near;
  };
  return stick;
}

void ContactSwitch::carry_to_stick(runtime::EventHit& hit, const std::vector<double>& direction) const {
  runtime::Sample s;
  s.t = hit.t;
  s.y = hit.y;
  s.yp = hit.yp;
  const auto along = [&](const runtime::Sample& at) {
    const std::vector<double> f = slip_on_sliding(at);
    double a = 0;
    for (std::size_t k = 0; k < direction.size(); ++k) a += f[k] * direction[k];
    return a;
  };
  const double h = 1e-6;
  runtime::Sample ahead = s;
  for (std::size_t i = 0; i < ahead.y.size(); ++i) ahead.y[i] += h * s.yp[i];
  const double g0 = along(s), slope = (along(ahead) - g0) / h;
  const double tau = slope < 0 ? -g0 / slope : 0.0;
  for (std::size_t i = 0; i < hit.y.size(); ++i) hit.y[i] += tau * hit.yp[i];
  hit.t += tau;
}

}  // namespace nhc::app
