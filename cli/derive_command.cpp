// nhc derive SCENE [--model M]... [--format text|latex|latex-math|json] [--form full|reduced]
//            [--speeds "u1',u2'"] [--set P=V]... [--expand] [-o FILE]
#include <iostream>

#include <fmt/format.h>

#include "commands.hpp"
#include "flag_rules.hpp"
#include "work_watchdog.hpp"
#include "nhc/app/parameter_overrides.hpp"
#include "nhc/app/model_requirements.hpp"
#include "nhc/expr/work_stage.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/derive/reduced_form.hpp"
#include "nhc/emit/derivation_emitters.hpp"
#include "nhc/io/atomic_file.hpp"
#include "nhc/io/output_path.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::cli {

namespace {

struct DeriveOptions {
  std::string scene_path;
  std::vector<std::string> models;
  std::string format = "text";
  std::string form = "full";
  std::string speeds;
  std::string output;
  std::vector<std::string> set;
  SceneOptions read;
};

}  // namespace

void add_work_limit_flag(CLI::App* sub) {
  sub->add_option_function<double>(
         "--work-limit",
         [](double seconds) {
           work_limit_seconds = seconds;
           work_limit_given = true;
         },
         "processor seconds the symbolic work (deriving, reducing, generating code) may take before the run "
         "is refused (default " +
             fmt::format("{:g}", work_budget::kDefaultWorkSeconds) + ", " +
             fmt::format("{:g}", work_budget::kDefaultWorkSeconds * kExpandedWorkFactor) + " with --expand)")
      ->check(flag_rules::positive())
      ->option_text("SECONDS");
}

void add_expand_flag(CLI::App* sub, SceneOptions& options) {
  sub->add_flag_callback(
      "--expand",
      [&options] {
        options.keep_definitions = false;
        work_expanded = true;  // a larger default budget (work_watchdog.hpp)
      },
      "substitute every definition into the equations (by default each stays a named quantity, "
      "listed after the equations)");
}

std::vector<ModelKind> selected_models(const Scene& scene, const std::vector<std::string>& names) {
  if (names.empty()) return scene.models;
  std::vector<ModelKind> kinds;
  for (const auto& n : names) kinds.push_back(*parse_model_kind(n));
  return kinds;
}

CommandRunner add_derive_command(CLI::App& app) {
  auto options = std::make_shared<DeriveOptions>();
  CLI::App* sub = app.add_subcommand("derive", "derive the equations of motion of a scene");
  sub->add_option("SCENE", options->scene_path, "scene file (TOML)")->required();
  sub->add_option("--model,-m", options->models, "model(s) to derive (default: the scene's)")
      ->check(CLI::IsMember(model_names()));
  sub->add_option("--format,-f", options->format, "output format")
      ->check(CLI::IsMember({"text", "latex", "latex-math", "json"}));
  sub->add_option("--form", options->form,
                  "full: the residuals with multipliers; reduced: also the multiplier-free form M_r u' = f_r on "
                  "independent speeds (chetaev and holder models, constraints linear in the velocities; "
                  "docs/reduced-form.md)")
      ->check(CLI::IsMember({"full", "reduced"}));
  sub->add_option("--speeds", options->speeds,
                  "the independent speeds of the reduced form, e.g. \"phi',delta',thr'\" (implies --form reduced; "
                  "default: the scene's dependent key, else the first coordinates whose constraint columns are "
                  "independent at the initial point)")
      ->option_text("LIST");
  add_set_option(sub, options->set);
  add_expand_flag(sub, options->read);
  add_work_limit_flag(sub);
  sub->add_option("-o,--output", options->output, "write to FILE instead of standard output");

  return [options]() {
    if (!options->output.empty()) check_output_file(options->output, {options->scene_path});
    Scene scene = load_scene(options->scene_path, options->read);
    app::apply_parameter_overrides(scene, app::parse_parameter_overrides(scene, options->set));
    std::vector<DerivedModel> models;
    for (ModelKind kind : selected_models(scene, options->models)) {
      if (!options->models.empty() || app::scene_lists_model(scene, kind)) app::require_model_inputs(scene, kind);
      models.push_back(derive_model(scene, kind));
    }
    if (options->form == "reduced" || !options->speeds.empty()) {
      const std::vector<std::string> speeds =
          options->speeds.empty() ? std::vector<std::string>{} : parse_speed_list(options->speeds);
      for (DerivedModel& model : models)
        model.reduced = std::make_shared<const ReducedForm>(reduce_to_independent_speeds(scene, model, speeds));
    }
    auto write = [&](std::ostream& out) {
      const work_budget::Stage stage("printing the equations");
      if (options->format == "latex") write_derivation_latex(out, scene, models);
      else if (options->format == "latex-math") write_derivation_latex_math(out, scene, models);
      else if (options->format == "json") write_derivation_json(out, scene, models);
      else write_derivation_text(out, scene, models);
    };
    if (options->output.empty()) write(std::cout);
    else write_file_atomically(options->output, write);
    return 0;
  };
}

}  // namespace nhc::cli
