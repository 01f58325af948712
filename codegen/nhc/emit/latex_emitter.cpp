#include "nhc/emit/derivation_emitters.hpp"
#include "nhc/jet/expression_printer.hpp"

namespace nhc {

namespace {

/// Scene names may contain '_', which is special in LaTeX text mode.
std::string latex_text(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c == '_' || c == '&' || c == '%' || c == '$' || c == '#' || c == '{' || c == '}')
      out += '\\';
    out += c;
  }
  return out;
}

}  // namespace

void write_derivation_latex(std::ostream& out, const Scene& scene,
                            const std::vector<DerivedModel>& models) {
  const JetSpace& jet = *scene.jet;
  out << "\\documentclass[10pt]{article}\n"
         "\\usepackage[margin=2cm,landscape]{geometry}\n"
         "\\usepackage{amsmath}\n"
         "\\allowdisplaybreaks\n"
         "\\begin{document}\n"
      << "\\section*{Scene \\texttt{" << latex_text(scene.name) << "}}\n"
      << "\\begin{align*}\n  L &= " << to_latex(scene.lagrangian);
  for (std::size_t a = 0; a < scene.constraints.size(); ++a)
    out << " \\\\\n  f^{" << a + 1 << "} &= " << to_latex(scene.constraints[a]);
  out << "\n\\end{align*}\n";
  for (const DerivedModel& model : models) {
    out << "\\subsection*{Model \\texttt{" << to_string(model.kind) << "}}\n";
    if (!model.applicable) {
      out << "Not applicable: " << latex_text(model.reason) << "\n";
      continue;
    }
    out << "\\begin{align*}\n";
    for (std::size_t i = 0; i < model.equations.size(); ++i) {
      if (i > 0) out << " \\\\\n";
      out << "  R_{" << i + 1 << "} &= " << to_latex(model.equations[i]) << " = 0";
    }
    for (std::size_t a = 0; a < model.constraints.size(); ++a)
      out << " \\\\\n  f^{" << a + 1 << "} &= " << to_latex(model.constraints[a]) << " = 0"
          << (model.constraints_are_equations ? "" : " \\quad\\text{(monitored)}");
    out << "\n\\end{align*}\n";
    (void)jet;
  }
  out << "\\end{document}\n";
}

}  // namespace nhc
