#include "nhc/runtime/trajectory.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "nhc/base/primed_name.hpp"
#include "nhc/base/number_text.hpp"

namespace nhc::runtime {

namespace {

/// For each unknown, the state holding its highest differential order: its y' is the next
/// derivative (x'' from the state x').
std::vector<int> highest_differential_states(const Model& model) {
  const int unknowns = model.n_coordinates() + model.n_multipliers();
  std::vector<int> result;
  for (int v = 0; v < unknowns; ++v) {
    int best = -1;
    for (int i = 0; i < model.n_states(); ++i)
      if (model.table().state_variable[i] == v && model.is_differential(i) &&
          (best < 0 || model.table().state_order[i] > model.table().state_order[best]))
        best = i;
    result.push_back(best);
  }
  return result;
}

}  // namespace

Observables observe(const Model& model, const std::vector<double>& parameters, const Sample& s) {
  Observables o;
  std::vector<double> scratch;
  observe(model, parameters, s, o, scratch);
  return o;
}

void observe(const Model& model, const std::vector<double>& parameters, const Sample& s, Observables& o,
             std::vector<double>& scratch) {
  const auto& tab = model.table();
  // The generated functions read the inputs after the parameters (inputs.hpp): the sample's.
  const double* p = parameters.data();
  if (model.n_inputs() > 0) {
    if (static_cast<int>(s.u.size()) != model.n_inputs())
      throw base::ModelError("a sample of a model with " + std::to_string(model.n_inputs()) + " inputs carries " +
                             std::to_string(s.u.size()) + " input values");
    scratch.assign(parameters.begin(), parameters.end());
    scratch.insert(scratch.end(), s.u.begin(), s.u.end());
    p = scratch.data();
  }
  o.hidden.resize(model.n_hidden());
  if (model.n_hidden() > 0) tab.hidden_constraints(s.t, s.y.data(), p, o.hidden.data());
  o.invariants.resize(model.n_invariants());
  if (model.n_invariants() > 0) tab.invariants(s.t, s.y.data(), s.yp.data(), p, o.invariants.data());
  const int nr = model.n_reference();
  o.errors.resize(nr);
  if (nr > 0) {
    tab.reference(s.t, p, o.errors.data());  // q_c(t), then the error in place
    for (int k = 0; k < nr; ++k) {
      const int i = model.state_index(tab.reference_coordinate[k], 0);
      o.errors[k] = i >= 0 ? s.y[i] - o.errors[k] : NAN;
    }
  }
}

DriftReport measure_drift(const Model& model, const std::vector<double>& p, const std::vector<Sample>& samples) {
  DriftReport d;
  d.max_hidden_each.assign(model.n_hidden(), 0.0);
  d.first_hidden_each.assign(model.n_hidden(), NAN);
  d.invariant_drift.assign(model.n_invariants(), 0.0);
  d.invariant_relative.assign(model.n_invariants(), 0.0);
  d.invariant_scale.assign(model.n_invariants(), 0.0);
  d.invariant_absolute.assign(model.n_invariants(), false);
  d.max_error_each.assign(model.n_reference(), 0.0);
  if (samples.empty()) return d;
  const Observables first = observe(model, p, samples.front());
  d.first_hidden_each = first.hidden;
  auto worse = [](double& acc, double v) { acc = std::isfinite(v) ? std::max(acc, std::abs(v)) : INFINITY; };
  for (const Sample& s : samples) {
    const Observables o = observe(model, p, s);
    for (size_t i = 0; i < o.hidden.size(); ++i)
      worse(d.max_hidden_each[i], o.hidden[i]), worse(d.max_hidden, o.hidden[i]);
    for (size_t k = 0; k < o.invariants.size(); ++k) {
      worse(d.invariant_drift[k], o.invariants[k] - first.invariants[k]);
      worse(d.invariant_scale[k], o.invariants[k]);
    }
    for (size_t k = 0; k < o.errors.size(); ++k)
      worse(d.max_error_each[k], o.errors[k]), worse(d.max_error, o.errors[k]);
  }
  for (size_t k = 0; k < d.invariant_drift.size(); ++k) {
    // Relative to the invariant's size along the run, max_t |I(t)| (not |I(t0)|, which may be
    // 0 or rounding noise: a pendulum released at its pivot height); absolute below the floor.
    d.invariant_absolute[k] = !(d.invariant_scale[k] >= kInvariantScaleFloor);
    d.invariant_relative[k] =
        d.invariant_absolute[k] ? d.invariant_drift[k] : d.invariant_drift[k] / d.invariant_scale[k];
    d.max_invariant_relative = std::max(d.max_invariant_relative, d.invariant_relative[k]);
  }
  return d;
}

std::string hidden_column(const Model& model, int i) {
  if (model.model_name() == "suslov") return "constraint:" + model.hidden_name(i);
  return "hidden:" + std::to_string(i + 1);
}

std::vector<std::string> csv_header(const Model& model) {
  const auto& tab = model.table();
  std::vector<std::string> h{"t"};
  const std::vector<int> top = highest_differential_states(model);
  const int unknowns = model.n_coordinates() + model.n_multipliers();
  for (int v = 0; v < unknowns; ++v) {
    for (int i = 0; i < model.n_states(); ++i)
      if (tab.state_variable[i] == v) h.push_back(model.state_name(i));
    if (top[v] >= 0) h.push_back(base::primed_name(model.state_name(top[v]), 1));
  }
  for (int k = 0; k < model.n_inputs(); ++k) h.push_back("input:" + model.input_name(k));
  for (int i = 0; i < model.n_hidden(); ++i) h.push_back(hidden_column(model, i));
  for (int k = 0; k < model.n_invariants(); ++k) h.push_back(std::string("invariant:") + tab.invariant_names[k]);
  for (int k = 0; k < model.n_reference(); ++k)
    h.push_back("error:" + model.variable_name(tab.reference_coordinate[k]));
  return h;
}

CsvRows::CsvRows(const Model& model, std::vector<double> parameters)
    : model_(model), parameters_(std::move(parameters)), top_(highest_differential_states(model)) {
  const auto& tab = model.table();
  const int unknowns = model.n_coordinates() + model.n_multipliers();
  // The states of each unknown, in state order: found once, not per row (a search over all
  // states for each unknown of each row was quadratic: 1.2 s of a 1.4 s run at 3584 states).
  states_of_.resize(static_cast<size_t>(unknowns));
  for (int i = 0; i < model.n_states(); ++i) states_of_[static_cast<size_t>(tab.state_variable[i])].push_back(i);
}

void CsvRows::row(const Sample& s, std::vector<double>& out) const {
  out.clear();
  out.push_back(s.t);
  for (std::size_t v = 0; v < states_of_.size(); ++v) {
    for (int i : states_of_[v]) out.push_back(s.y[static_cast<std::size_t>(i)]);
    if (top_[v] >= 0) out.push_back(s.yp[static_cast<std::size_t>(top_[v])]);
  }
  out.insert(out.end(), s.u.begin(), s.u.end());
  observe(model_, parameters_, s, observed_, scratch_);
  const Observables& o = observed_;
  out.insert(out.end(), o.hidden.begin(), o.hidden.end());
  out.insert(out.end(), o.invariants.begin(), o.invariants.end());
  out.insert(out.end(), o.errors.begin(), o.errors.end());
}

void write_csv(std::ostream& out, const Model& model, const std::vector<double>& p,
               const std::vector<Sample>& samples) {
  const std::vector<std::string> header = csv_header(model);
  for (size_t c = 0; c < header.size(); ++c) out << (c ? "," : "") << header[c];
  out << '\n';
  const CsvRows rows(model, p);
  std::vector<double> values;
  std::string row;
  for (const Sample& s : samples) {
    rows.row(s, values);
    row.clear();
    for (double x : values) base::append_shortest(row, ',', x);
    row.erase(0, 1);  // the first column has no comma
    row += '\n';
    out << row;
  }
}

void write_csv(const std::string& path, const Model& model, const std::vector<double>& p,
               const std::vector<Sample>& samples) {
  const std::string tmp = path + ".tmp" + std::to_string(getpid());
  {
    std::ofstream out(tmp);
    if (!out) throw std::runtime_error("cannot write " + tmp);
    write_csv(out, model, p, samples);
    out.flush();
    if (!out) {
      std::remove(tmp.c_str());
      throw std::runtime_error("cannot write " + tmp);
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::remove(tmp.c_str());
    throw std::runtime_error("cannot rename " + tmp + " to " + path);
  }
}

RunResult simulate(const Model& model, const std::vector<double>& p, const InitialState& initial,
                   const std::vector<double>& times, const IntegratorOptions& options, const std::vector<Event>& events,
                   const InputFunction& inputs) {
  RunResult result;
  Integrator integrator(model, p, options);
  for (const Event& e : events) integrator.add_event(e);
  if (inputs) integrator.set_inputs(inputs);
  try {
    const double t_next = first_output_after(times, initial.t0);
    result.initial = integrator.initialize(initial, t_next);
    integrator.integrate(times, [&](const Sample& s) { result.samples.push_back(s); });
  } catch (const base::SolverError& e) {
    result.failure = e;
  }
  result.statistics = integrator.statistics();
  result.events = integrator.events();
  return result;
}

}  // namespace nhc::runtime
