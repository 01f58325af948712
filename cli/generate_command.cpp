// nhc generate SCENE [--model M] [--jacobian dense|sparse|none] [--set P=V]... [-o DIR]
//              [--print-file-name]
//
// Writes DIR/<scene>_<model>.hpp (docs/generated-code.md); with --print-file-name only prints
// that file name (for build systems: nhc_add_model asks instead of parsing the scene). The model defaults to the
// scene's [simulate] model, else chetaev when the scene lists it, else the scene's first model: the model one would
// integrate.
#include <filesystem>
#include <iostream>

#include "commands.hpp"
#include "nhc/app/parameter_overrides.hpp"
#include "flag_rules.hpp"
#include "nhc/app/model_requirements.hpp"
#include "nhc/analysis/index1_reduction.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/derive/reduced_form.hpp"
#include "nhc/emit/header_emitter.hpp"
#include "nhc/io/atomic_file.hpp"
#include "nhc/io/output_path.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::cli {

namespace {

struct GenerateOptions {
  std::string scene_path;
  std::string model;
  std::string jacobian = "dense";
  std::string directory = ".";
  bool quiet = false;
  bool reduced_form = false;
  bool sensitivities = false;
  bool variational = false;
  bool print_file_name = false;
  std::vector<std::string> set;
  SceneOptions read;
};

}  // namespace

CommandRunner add_generate_command(CLI::App& app) {
  auto options = std::make_shared<GenerateOptions>();
  CLI::App* sub =
      app.add_subcommand("generate", "write a self-contained C++ header with the index-1 residual of one model");
  sub->add_option("SCENE", options->scene_path, "scene file (TOML)")->required();
  sub->add_option("--model,-m", options->model, "model (default: the scene's [simulate] model, else chetaev)")
      ->check(CLI::IsMember(model_names()));
  sub->add_option("--jacobian,-j", options->jacobian,
                  "Jacobian dF/dy + cj dF/dy': dense (column-major), sparse (compressed column) or "
                  "none")
      ->check(CLI::IsMember({"dense", "sparse", "none"}));
  sub->add_option("-o,--output-dir", options->directory, "directory to write <scene>_<model>.hpp into (default: .)");
  sub->add_flag("--sensitivities", options->sensitivities,
                "also dF/dp and dg/dp for forward sensitivities (docs/generated-code.md)");
  sub->add_flag("--variational", options->variational,
                "also the discrete Lagrange-d'Alembert step of the chetaev model (docs/variational.md)");
  sub->add_flag("--print-file-name", options->print_file_name,
                "print the header's file name (<scene>_<model>.hpp) and write nothing");
  add_set_option(sub, options->set);
  add_expand_flag(sub, options->read);
  add_work_limit_flag(sub);
  sub->add_flag("-q,--quiet", options->quiet, "do not print the written file and operation counts");
  sub->add_flag("--reduced-form", options->reduced_form,
                "also emit mass_matrix, forcing and velocities of the multiplier-free form (docs/reduced-form.md)");

  return [options]() {
    if (options->print_file_name) {
      const Scene scene = load_scene(options->scene_path, options->read);
      std::cout << generated_header_file_name(scene.name, model_or_default(scene, options->model)) << "\n";
      return 0;
    }
    check_output_directory(options->directory, {options->scene_path});
    Scene scene = load_scene(options->scene_path, options->read);
    app::apply_parameter_overrides(scene, app::parse_parameter_overrides(scene, options->set));
    const ModelKind kind = model_or_default(scene, options->model);
    app::require_model_inputs(scene, kind);
    const DerivedModel derived = derive_model(scene, kind);
    if (!derived.applicable)
      throw MathError("the " + to_string(kind) + " model does not apply to " + scene.name + ": " + derived.reason);
    const Index1System system = reduce_to_index1(scene, derived);
    // The multiplier-free form where the model has one (docs/reduced-form.md), on the default speeds.
    std::optional<ReducedForm> reduced;
    if (options->reduced_form) reduced = reduce_to_independent_speeds(scene, derived);
    HeaderOptions header_options;
    header_options.reduced = reduced ? &*reduced : nullptr;
    header_options.jacobian = *parse_jacobian_kind(options->jacobian);
    header_options.sensitivities = options->sensitivities;
    header_options.variational = options->variational;
    const GeneratedHeader header = generate_header(scene, system, header_options);

    std::error_code ignored;  // an unwritable directory is reported by the write below
    std::filesystem::create_directories(options->directory, ignored);
    std::string path = options->directory;
    if (!path.empty() && path.back() != '/') path += '/';
    path += header.file_name;
    check_output_file(path, {options->scene_path});
    write_file_atomically(path, [&](std::ostream& out) { out << header.text; });
    if (!options->quiet)
      std::cout << path << ": " << system.size() << " states, operations "
                << operation_count_text(header.before_cse.total()) << " before CSE, "
                << operation_count_text(header.after_cse.total()) << " after\n";
    return 0;
  };
}

}  // namespace nhc::cli
