#include "input_laws.hpp"

#include <cctype>
#include <set>
#include <stdexcept>

#include "nhc/errors.hpp"
#include "nhc/scene/expression_parser.hpp"
#include "nhc/scene/scene_text.hpp"

namespace nhc::app {

namespace {

/// True when `text` names one of the scene's [definitions] (an identifier that is one).
bool names_a_definition(const Scene& scene, const std::string& text) {
  const std::set<std::string> definitions = scene_definition_names(scene.source_text());
  if (definitions.empty()) return false;
  for (std::size_t k = 0; k < text.size();) {
    const auto starts = [&](char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; };
    const auto continues = [&](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
    if (!starts(text[k])) {
      ++k;
      continue;
    }
    std::size_t end = k;
    while (end < text.size() && continues(text[end])) ++end;
    if (definitions.count(text.substr(k, end - k))) return true;
    k = end;
  }
  return false;
}

}  // namespace

bool is_feedback_law(const Scene& scene, const std::string& name, const std::string& text, const std::string& field) {
  if (!scene.jet->input_index(name)) return false;
  ExpressionRules rules;
  rules.allow_inputs = false;
  GiNaC::ex law;
  try {
    law = parse_expression(text, *scene.jet, rules);
  } catch (const std::exception&) {
    // The [definitions] are the scene reader's: an expression that names one is read there, as
    // if written in [inputs] (a law, or a signal of t through them); any other is the signal
    // reader's to judge.
    return !scene.source_text().empty() && names_a_definition(scene, text);
  }
  const int order = scene.jet->highest_coordinate_order(law);
  // As for a law in the file (scene_loader.cpp): the states hold q and q', q'' is what the input drives.
  if (order > 1)
    throw InputError({field, 0, 0}, name + "=" + text + ": uses a derivative of order " + std::to_string(order) +
                                        " of a coordinate: an algebraic loop (the input drives the accelerations it "
                                        "would read); a feedback law may use t, parameters, coordinates and their "
                                        "first derivatives");
  return order >= 0;
}

Scene scene_with_input_laws(const Scene& scene, const std::map<std::string, std::string>& laws,
                            const SceneOptions& options, const std::string& field) {
  if (laws.empty()) return scene;
  std::string text;
  try {
    text = scene_text_with_inputs(scene.source_text(), laws);
  } catch (const std::exception& e) {
    throw InputError({field, 0, 0}, e.what());
  }
  Scene closed;
  try {
    closed = parse_scene(text, scene.source_path, options);
  } catch (const InputError& error) {
    // The rewritten text is nowhere on disk: the error is the flag's, naming the laws given.
    std::string given;
    for (const auto& [name, law] : laws) given += (given.empty() ? "" : ", ") + name + "=" + law;
    throw InputError({field, 0, 0}, given + ": " + error.message());
  }
  closed.parameter_values = scene.parameter_values;
  closed.initial = scene.initial;
  return closed;
}

}  // namespace nhc::app
