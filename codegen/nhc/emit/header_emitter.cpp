// The header emitter (header_emitter.hpp): preparation (model_preparation.hpp), then printing
// (header_printer.hpp).
#include "nhc/expr/work_stage.hpp"
#include "nhc/emit/header_emitter.hpp"

#include <cstdio>

#include "nhc/emit/header_printer.hpp"
#include "nhc/emit/model_preparation.hpp"
#include "nhc/errors.hpp"

namespace nhc {

std::string to_string(JacobianKind kind) {
  switch (kind) {
    case JacobianKind::dense:
      return "dense";
    case JacobianKind::sparse:
      return "sparse";
    case JacobianKind::none:
      return "none";
  }
  return "dense";
}

std::optional<JacobianKind> parse_jacobian_kind(const std::string& name) {
  for (JacobianKind k : {JacobianKind::dense, JacobianKind::sparse, JacobianKind::none})
    if (to_string(k) == name) return k;
  return std::nullopt;
}

std::string sanitize_comment(const std::string& text) {
  // Decided on the output, not the input: a replacement must not form a sequence either
  // ("\xff\xff/" would otherwise become the trigraph "??/", a line splice in C++14).
  std::string out;
  auto put = [&out](char c) {
    if (!out.empty() && ((out.back() == '*' && c == '/') || (out.back() == '?' && c == '?')))
      out += ' ';  // "* /" cannot close a comment, "? ?" is no trigraph
    out += c;
  };
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '\\') put('/');  // no line splicing
    else if (c == '\n' || c == '\r' || c == '\t') put(' ');
    else if (c < 0x20 || c >= 0x7f) put('?');  // ASCII only: no U+2028, no invalid UTF-8
    else put(ch);
  }
  return out;
}

std::string cpp_string_literal(const std::string& text) {
  std::string out = "\"";
  for (char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += ch;
    } else if (c < 0x20 || c >= 0x7f || c == '?') {
      char octal[8];
      std::snprintf(octal, sizeof octal, "\\%03o", static_cast<unsigned>(c));
      out += octal;
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

std::string generated_namespace_name(const std::string& scene_name, ModelKind model) {
  return scene_name + "_" + to_string(model);
}

std::string generated_header_file_name(const std::string& scene_name, ModelKind model) {
  return generated_namespace_name(scene_name, model) + ".hpp";
}

GeneratedHeader generate_header(const Scene& scene, const Index1System& system, const HeaderOptions& options,
                                PreparedModel* prepared) {
  const work_budget::Stage stage("generating code (Jacobians, CSE, printing)");
  if (!system.jet) throw MathError("index-1 system without a jet space");
  // The scene name becomes a namespace and a file name: only a validated identifier may. (Scenes
  // built in code skip the loader's checks; every other name only enters comments and literals.)
  if (!is_valid_identifier(scene.name))
    throw InputError({scene.source_path.empty() ? "scene" : scene.source_path, 0, 0},
                     "invalid scene name '" + sanitize_comment(scene.name) + "': it must be a C++ identifier");
  const size_t n = system.states.size();
  if (system.residuals.size() != n || system.y.size() != n || system.yp.size() != n)
    throw MathError("inconsistent index-1 system: " + std::to_string(n) + " states, " +
                    std::to_string(system.residuals.size()) + " residuals");
  PreparedModel model =
      refusing_at(scene.file_location(), "generating code for the " + to_string(system.model) + " model", [&] {
        return prepare_model(scene, system, options.jacobian, options.sensitivities, options.variational,
                             options.reduced);
      });
  GeneratedHeader header;
  header.namespace_name = model.namespace_name;
  header.file_name = generated_header_file_name(scene.name, system.model);
  header.text = print_header(scene, system, model, options.split_from_bytes);
  header.before_cse = model.before_cse;
  header.after_cse = model.after_cse;
  if (prepared) *prepared = std::move(model);
  return header;
}

}  // namespace nhc
