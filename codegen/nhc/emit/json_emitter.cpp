#include <set>

#include "nhc/derive/reduced_form.hpp"
#include "nhc/emit/derivation_emitters.hpp"
#include "nhc/expr/expression_printer.hpp"
#include "nhc/emit/json_writer.hpp"
#include "nhc/expr/intermediate.hpp"

namespace nhc {

namespace {

/// "reduced": M_r u' = f_r on the independent speeds (docs/reduced-form.md), its expressions in
/// the printed form of "equations" (over "symbols" and "definitions").
void write_reduced_json(JsonWriter& json, const ReducedForm& r) {
  json.key("reduced").begin_object();
  json.key("available").value(r.available);
  if (!r.available) {
    json.key("reason").value(r.reason);
    json.end_object();
    return;
  }
  auto names = [&](const char* key, const std::vector<std::string>& list) {
    json.key(key).begin_array();
    for (const auto& n : list) json.value(n);
    json.end_array();
  };
  auto expressions = [&](const char* key, const std::vector<GiNaC::ex>& list) {
    json.key(key).begin_array();
    for (const auto& e : list) json.value(to_text(e));
    json.end_array();
  };
  names("speeds", r.speeds);
  json.key("rule").value(r.rule);
  names("dependent", r.dependent_names);
  expressions("dependent_speeds", r.dependent_speeds);
  json.key("mass_matrix").begin_array();
  for (unsigned i = 0; i < r.mass_matrix.rows(); ++i) {
    json.begin_array();
    for (unsigned j = 0; j < r.mass_matrix.cols(); ++j) json.value(to_text(r.mass_matrix(i, j)));
    json.end_array();
  }
  json.end_array();
  expressions("forcing", r.forcing);
  names("multiplier_names", r.multiplier_names);
  expressions("multipliers", r.multipliers);
  json.end_object();
}

}  // namespace

void write_derivation_json(std::ostream& out, const Scene& scene, const std::vector<DerivedModel>& models) {
  const JetSpace& jet = *scene.jet;
  JsonWriter json(out);
  json.begin_object();
  json.key("scene").value(scene.name);
  json.key("parameters").begin_array();
  for (const auto& p : jet.parameters()) json.value(p);
  json.end_array();

  // Every jet symbol that occurs in a printed expression, with what it is a derivative of.
  std::set<JetCoordinate> used;
  auto note = [&](const GiNaC::ex& e) {
    for (const auto& c : jet.jet_coordinates_in(e)) used.insert(c);
  };
  const std::vector<GiNaC::ex> where = derivation_intermediates(scene, models);
  for (const DerivedModel& model : models) {
    for (const auto& e : model.equations) note(e);
    for (const auto& e : model.constraints) note(e);
    if (model.reduced && model.reduced->available) {
      for (const auto& e : model.reduced->expressions()) note(e);
      for (const auto& e : model.reduced->dependent_symbols) note(e);
      for (int i : model.reduced->independent) note(jet.q(i, 1)), note(jet.q(i, 2));
    }
  }
  json.key("symbols").begin_object();
  for (const JetCoordinate& c : used) {
    const std::string of = jet.variable_name(c.kind, c.index);
    json.key(jet_symbol_name(of, c.order)).begin_object();
    json.key("of").value(of);
    json.key("order").value(c.order);
    json.end_object();
  }
  json.end_object();

  json.key("definitions").begin_array();
  for (const GiNaC::ex& d : where) {
    const auto& i = GiNaC::ex_to<Intermediate>(d);
    json.begin_object();
    json.key("name").value(i.intermediate_name());
    json.key("expression").value(to_text(i.expression()));
    json.end_object();
  }
  json.end_array();

  json.key("models").begin_object();
  for (const DerivedModel& model : models) {
    json.key(to_string(model.kind)).begin_object();
    json.key("applicable").value(model.applicable);
    if (!model.applicable) {
      json.key("reason").value(model.reason);
      json.end_object();
      continue;
    }
    json.key("equations").begin_array();
    for (const auto& e : model.equations) json.value(to_text(e));
    json.end_array();
    // The equations' names, as the text and LaTeX forms write them: R_<coordinate>.
    json.key("equation_names").begin_array();
    for (std::size_t i = 0; i < model.equations.size(); ++i) json.value("R_" + scene.jet->coordinates().at(i));
    json.end_array();
    // Every model lists its constraints under the same key; "constraints_solved" says whether
    // the model solves them (vakonomic, chetaev, holder) or only monitors them (suslov).
    json.key("constraints").begin_array();
    for (const auto& e : model.constraints) json.value(to_text(e));
    json.end_array();
    json.key("constraints_solved").value(model.constraints_are_equations);
    json.key("multipliers").begin_array();
    for (const auto& m : model.multipliers) json.value(m);
    json.end_array();
    if (model.reduced) write_reduced_json(json, *model.reduced);
    json.end_object();
  }
  json.end_object();
  json.end_object();
}

}  // namespace nhc
