#include "nhc/emit/analysis_emitters.hpp"
#include "nhc/emit/json_writer.hpp"

namespace nhc {

namespace {

void write_one(JsonWriter& json, const ModelAnalysis& m) {
  json.begin_object();
  json.key("model").value(to_string(m.model));
  json.key("applicable").value(m.applicable);
  const StructuralAnalysis* a = m.structure ? &*m.structure : nullptr;
  const bool offsets = a && !a->structurally_singular;
  json.key("unknowns").begin_array();
  if (a)
    for (const auto& u : a->system.unknowns) json.value(u.name);
  json.end_array();
  json.key("equations").begin_array();
  if (a)
    for (const auto& e : a->system.equation_names) json.value(e);
  json.end_array();
  json.key("sigma").begin_array();
  if (a)
    for (int i = 0; i < a->sigma.rows(); ++i) {
      json.begin_array();
      int j = 0;  // the row's finite entries, by column, with nulls between
      for (const auto& e : a->sigma.row(i)) {
        for (; j < e.col; ++j) json.null();
        json.value(e.value);
        ++j;
      }
      for (; j < a->sigma.cols(); ++j) json.null();
      json.end_array();
    }
  json.end_array();
  auto ints = [&](const char* key, const std::vector<int>& v) {
    json.key(key);
    if (!offsets) {
      json.null();
      return;
    }
    json.begin_array();
    for (int x : v) json.value(x);
    json.end_array();
  };
  ints("c", offsets ? a->offsets.c : std::vector<int>{});
  ints("d", offsets ? a->offsets.d : std::vector<int>{});
  json.key("index");
  if (offsets) json.value(a->index);
  else json.null();
  json.key("dof");
  if (offsets) json.value(a->dof);
  else json.null();
  json.key("initial_values_needed").begin_array();
  if (offsets)
    for (const JetCoordinate& c : a->initial_values_needed)
      json.value(prime_name(a->system.jet->variable_name(c.kind, c.index), c.order));
  json.end_array();
  json.key("hidden_constraints").begin_array();
  if (offsets)
    for (const HiddenConstraint& h : a->hidden_constraints) json.value(h.name);
  json.end_array();
  json.key("jacobian_condition");
  if (m.jacobian) json.value(m.jacobian_condition);  // +∞ (exactly singular) prints as null
  else json.null();
  json.key("jacobian_condition_estimated");  // true: a 1-norm estimate (above kExactConditionLimit unknowns)
  if (m.jacobian) json.value(m.jacobian_condition_estimated);
  else json.null();
  json.key("initial_values").begin_object();
  if (m.initial) {
    for (const auto* list : {&m.initial->values, &m.initial->leading})
      for (const InitialValue& v : *list) {
        json.key(v.name).begin_object();
        json.key("value").value(v.value);
        json.key("source").value(to_string(v.source));
        json.end_object();
      }
  }
  json.end_object();
  json.key("notes").begin_array();
  if (m.initial)
    for (const auto& n : m.initial->notes) json.value(n);
  json.end_array();
  json.key("errors").begin_array();
  for (const auto& e : m.errors) json.value(e);
  json.end_array();
  json.end_object();
}

}  // namespace

void write_analysis_json(std::ostream& out, const Scene& /*scene*/, const std::vector<ModelAnalysis>& analyses) {
  JsonWriter json(out);
  if (analyses.size() == 1) {
    write_one(json, analyses.front());
  } else {
    json.begin_array();
    for (const auto& m : analyses) write_one(json, m);
    json.end_array();
    out << "\n";
  }
}

}  // namespace nhc
