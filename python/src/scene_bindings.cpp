#include "scene_bindings.hpp"

#include "nhc/base/primed_name.hpp"

#include <pybind11/stl.h>

#include <sstream>

#include "nhc/analysis/model_analysis.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/derive/reduced_form.hpp"
#include "nhc/emit/derivation_emitters.hpp"
#include "model_argument.hpp"
#include "nhc/app/parameter_values.hpp"
#include "nhc/app/run_request.hpp"
#include "nhc/errors.hpp"
#include "nhc/scene/scene.hpp"
#include "symbolic_work.hpp"

namespace py = pybind11;

namespace nhc::python {

namespace {

/// --set NAME=VALUE for a scene in memory: the values replace the parameters', and the [initial]
/// values written through parameters follow (as in the command line).
void set_parameters(Scene& scene, const std::map<std::string, double>& values) {
  std::vector<std::pair<std::string, double>> checked;
  for (const auto& [name, value] : values) {
    app::check_parameter_value(scene, name, value, "set", "set " + name);  // the rule of --set
    checked.emplace_back(name, value);
  }
  app::set_parameter_values(scene, checked);
}

/// One model's derivation in the three forms of `nhc derive`.
struct Derivation {
  std::string model, text, latex, latex_math, json;
};

Derivation derive(const Scene& scene, const std::string& model) {
  Derivation d;
  d.model = model;
  std::vector<DerivedModel> models;
  symbolic_work([&] { models.push_back(derive_model(scene, model_named(model))); });
  if (!models.front().applicable)
    throw MathError("the " + model + " model does not apply to " + scene.name + ": " + models.front().reason);
  std::ostringstream text, latex, latex_math, json;
  write_derivation_text(text, scene, models);
  write_derivation_latex(latex, scene, models);
  write_derivation_latex_math(latex_math, scene, models);
  write_derivation_json(json, scene, models);
  d.text = text.str();
  d.latex = latex.str();
  d.latex_math = latex_math.str();
  d.json = json.str();
  return d;
}

/// `nhc derive --format json --speeds …` of one model: its JSON with the multiplier-free form
/// (speeds empty: the default rule). Refused (MathError) when the model has no such form.
std::string reduced_json(const Scene& scene, const std::string& model, const std::vector<std::string>& speeds) {
  std::vector<DerivedModel> models;
  symbolic_work([&] {
    models.push_back(derive_model(scene, model_named(model)));
    if (!models.front().applicable)
      throw MathError("the " + model + " model does not apply to " + scene.name + ": " + models.front().reason);
    models.front().reduced =
        std::make_shared<const ReducedForm>(reduce_to_independent_speeds(scene, models.front(), speeds, "speeds"));
  });
  std::ostringstream json;
  write_derivation_json(json, scene, models);
  return json.str();
}

/// `nhc analyze` of one model: index, degrees of freedom, the initial values it needs and the
/// consistent initial point (name → value: the values, then the leading derivatives).
py::dict analyze(const Scene& scene, const std::string& model) {
  const ModelAnalysis a = symbolic_work([&] {
    const DerivedModel derived = derive_model(scene, model_named(model));
    if (!derived.applicable)
      throw MathError("the " + model + " model does not apply to " + scene.name + ": " + derived.reason);
    return analyze_model(scene, derived);
  });
  py::dict out;
  out["model"] = model;
  if (!a.structure) throw MathError("the structural analysis of the " + model + " model failed");
  const StructuralAnalysis& s = *a.structure;
  out["index"] = s.index;
  out["dof"] = s.dof;
  py::list needed;
  for (const JetCoordinate& c : s.initial_values_needed)  // x, x', lambda1: the scene's spelling
    needed.append(base::primed_name(scene.jet->variable_name(c.kind, c.index), c.order));
  out["needed"] = needed;
  py::dict point;
  if (a.initial) {
    for (const InitialValue& v : a.initial->values) point[py::str(v.name)] = v.value;
    if (a.initial->leading_solved)
      for (const InitialValue& v : a.initial->leading) point[py::str(v.name)] = v.value;
  }
  out["initial_point"] = point;
  out["condition"] = a.jacobian_condition;
  return out;
}

}  // namespace

void register_scene(py::module_& m) {
  py::class_<Derivation>(m, "_Derivation")
      .def_readonly("model", &Derivation::model)
      .def_readonly("text", &Derivation::text)
      .def_readonly("latex", &Derivation::latex)
      .def_readonly("latex_math", &Derivation::latex_math)
      .def_readonly("json", &Derivation::json);

  py::class_<Scene>(m, "_Scene")
      .def_static(
          "load",
          [](const std::string& path, const std::map<std::string, double>& set, bool expand) {
            SceneOptions options;
            options.keep_definitions = !expand;
            Scene scene = symbolic_work([&] { return load_scene(path, options); });
            set_parameters(scene, set);
            return scene;
          },
          py::arg("path"), py::arg("set") = std::map<std::string, double>{}, py::arg("expand") = false)
      .def_static(
          "from_toml",
          [](const std::string& text, const std::string& path, const std::map<std::string, double>& set, bool expand) {
            SceneOptions options;
            options.keep_definitions = !expand;
            Scene scene = symbolic_work([&] { return parse_scene(text, path, options); });
            set_parameters(scene, set);
            return scene;
          },
          py::arg("text"), py::arg("path") = "scene.toml", py::arg("set") = std::map<std::string, double>{},
          py::arg("expand") = false)
      .def(
          "with_parameters",
          [](const Scene& scene, const std::map<std::string, double>& set) {
            Scene changed = scene;
            set_parameters(changed, set);
            return changed;
          },
          py::arg("set"))
      .def_readonly("name", &Scene::name)
      .def_readonly("source_path", &Scene::source_path)
      .def_property_readonly("coordinates", [](const Scene& s) { return s.jet->coordinates(); })
      .def_property_readonly("parameters",
                             [](const Scene& s) {
                               std::map<std::string, double> out;
                               for (std::size_t k = 0; k < s.parameter_values.size(); ++k)
                                 out[s.jet->parameters()[k]] = s.parameter_values[k];
                               return out;
                             })
      .def_property_readonly("inputs", [](const Scene& s) { return s.jet->inputs(); })
      .def_property_readonly("models",
                             [](const Scene& s) {
                               std::vector<std::string> out;
                               for (ModelKind k : s.models) out.push_back(to_string(k));
                               return out;
                             })
      .def_property_readonly("default_model", [](const Scene& s) { return to_string(default_model(s)); })
      .def("derive", &derive, py::arg("model"))
      .def("reduced_json", &reduced_json, py::arg("model"), py::arg("speeds"))
      .def("analyze", &analyze, py::arg("model"));
}

}  // namespace nhc::python
