// nhc analyze SCENE [--model M]... [--format text|json] [--repair-initial [--write-initial FILE]]
//             [--set P=V]... [-o FILE]
// Pryce's structural analysis of each model, its consistent initial point and the system
// Jacobian there, reported per model. Exit 3 (with the reasons in words on standard error) when
// a requested model — those of --model, else the scene's default model — is not applicable,
// structurally singular, has inconsistent initial data or a singular system Jacobian at t0; the
// other models' failures are notes. A requested suslov model without `dependent` is bad input.
#include <algorithm>
#include <iostream>

#include "commands.hpp"
#include "nhc/app/parameter_overrides.hpp"
#include "flag_rules.hpp"
#include "write_initial.hpp"
#include "nhc/app/model_requirements.hpp"
#include "nhc/analysis/model_analysis.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/emit/analysis_emitters.hpp"
#include "nhc/errors.hpp"
#include "nhc/io/atomic_file.hpp"
#include "nhc/io/output_path.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::cli {

namespace {

struct AnalyzeOptions {
  std::string scene_path;
  std::vector<std::string> models;
  std::string format = "text";
  std::string output;
  bool repair = false;
  std::vector<std::string> set;
  std::string write_initial;
  SceneOptions read;
};

}  // namespace

CommandRunner add_analyze_command(CLI::App& app) {
  auto options = std::make_shared<AnalyzeOptions>();
  CLI::App* sub = app.add_subcommand("analyze",
                                     "structural analysis (Pryce's Sigma-method), index, degrees of freedom and "
                                     "consistent initial values of a scene's models");
  sub->add_option("SCENE", options->scene_path, "scene file (TOML)")->required();
  sub->add_option("--model,-m", options->models, "model(s) to analyse (default: the scene's)")
      ->check(CLI::IsMember(model_names()));
  sub->add_option("--format,-f", options->format, "output format (json: one object per model, an array when several)")
      ->check(CLI::IsMember({"text", "json"}));
  sub->add_flag("--repair-initial", options->repair,
                "move given initial values that violate a hidden constraint to the nearest "
                "consistent point instead of failing");
  sub->add_option("--write-initial", options->write_initial,
                  "write the consistent initial point of the (first requested) model as an [initial] table")
      ->needs("--repair-initial");
  add_set_option(sub, options->set);
  add_expand_flag(sub, options->read);
  add_work_limit_flag(sub);
  sub->add_option("-o,--output", options->output, "write to FILE instead of standard output");

  return [options]() {
    if (!options->output.empty()) check_output_file(options->output, {options->scene_path});
    if (!options->write_initial.empty()) check_output_file(options->write_initial, {options->scene_path});
    Scene scene = load_scene(options->scene_path, options->read);
    app::apply_parameter_overrides(scene, app::parse_parameter_overrides(scene, options->set));
    InitializationOptions init;
    init.repair = options->repair;
    std::vector<ModelAnalysis> analyses;
    const std::vector<ModelKind> kinds = selected_models(scene, options->models);
    std::vector<ModelKind> requested = selected_models(scene, options->models);
    if (options->models.empty()) requested = {default_model(scene)};
    auto is_requested = [&](ModelKind k) {
      return std::find(requested.begin(), requested.end(), k) != requested.end();
    };
    for (ModelKind kind : kinds)
      if (is_requested(kind)) app::require_model_inputs(scene, kind);
    for (ModelKind kind : kinds) analyses.push_back(analyze_model(scene, derive_model(scene, kind), init));
    auto write = [&](std::ostream& out) {
      if (options->format == "json") write_analysis_json(out, scene, analyses);
      else write_analysis_text(out, scene, analyses);
    };
    if (options->output.empty()) write(std::cout);
    else write_file_atomically(options->output, write);
    std::cout.flush();
    std::string failures;
    bool repairable = false;
    for (const auto& a : analyses) {
      if (!is_requested(a.model)) {
        for (const auto& e : a.errors) std::cerr << "nhc: note: " << e << " (not requested: exit 0)\n";
        continue;
      }
      for (const auto& e : a.errors) failures += (failures.empty() ? "" : "\nnhc: error: ") + e;
      repairable = repairable || a.initial_values_repairable;
    }
    if (repairable) failures += "\nnhc: note: --repair-initial moves the given values to the nearest consistent point";
    if (!failures.empty()) throw MathError(failures);
    if (!options->write_initial.empty())
      for (const auto& a : analyses)
        if (is_requested(a.model) && a.initial) {
          write_file_atomically(options->write_initial, [&](std::ostream& out) {
            write_initial_table(out, scene, to_string(a.model), *a.initial);
          });
          std::cerr << "nhc: wrote the " << to_string(a.model) << " model's initial point to " << options->write_initial
                    << "\n";
          break;
        }
    return 0;
  };
}

}  // namespace nhc::cli
