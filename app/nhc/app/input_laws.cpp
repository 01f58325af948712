#include "input_laws.hpp"

#include <stdexcept>

#include "nhc/errors.hpp"
#include "nhc/scene/expression_parser.hpp"
#include "nhc/scene/scene_text.hpp"

namespace nhc::app {

bool is_feedback_law(const Scene& scene, const std::string& name, const std::string& text, const std::string& field) {
  if (!scene.jet->input_index(name)) return false;
  ExpressionRules rules;
  rules.allow_inputs = false;
  GiNaC::ex law;
  try {
    law = parse_expression(text, *scene.jet, rules);
  } catch (const std::exception&) {
    return false;
  }
  const int order = scene.jet->highest_coordinate_order(law);
  // As for a law in the file (scene_loader.cpp): the states hold q and q', q'' is what the input drives.
  if (order > 1)
    throw InputError({field, 0, 0}, field + " " + name + "=" + text + ": uses a derivative of order " +
                                        std::to_string(order) +
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
    throw InputError({field, 0, 0}, field + ": " + e.what());
  }
  Scene closed = parse_scene(text, scene.source_path, options);
  closed.parameter_values = scene.parameter_values;
  closed.initial = scene.initial;
  return closed;
}

}  // namespace nhc::app
