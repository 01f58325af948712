// The nhc front end as a library (nhc::codegen; docs/library.md): Appell–Hamel built in code,
// derived under Chetaev's model, analysed with Pryce's Σ-method, reduced to index 1 and emitted
// as LaTeX and as the C++ header `nhc generate` would write.
//
// Check (models.md, closed form): the consistent initial point from x' = 1, y' = 0.5 has
// z' = k v0 and λ = m g/(1 + k^2), k = b/a, v0 = |(x', y')|; the structural index is 2 (the
// first-order constraint is differentiated once). Exit code 0 when these hold to 1e-10.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>

#include "nhc/codegen.hpp"

int main() {
  const double m = 1.0, g = 9.81, a = 1.0, b = 0.5;
  const nhc::Scene scene = nhc::SceneBuilder("appell_hamel")
                               .coordinates({"x", "y", "z"})
                               .parameter("m", m)
                               .parameter("g", g)
                               .parameter("a", a)
                               .parameter("b", b)
                               .lagrangian("m/2*(x'^2 + y'^2 + z'^2) - m*g*z")
                               .constraint("z' - b/a*sqrt(x'^2 + y'^2)")
                               .initial("x", {0.0, 1.0})
                               .initial("y", {0.0, 0.5})
                               .initial("z", {0.0})
                               .build();

  // Derive: the residuals R_i of models.md, printed as a LaTeX document.
  const nhc::DerivedModel chetaev = nhc::derive_model(scene, nhc::ModelKind::chetaev);
  std::ofstream latex("appell_hamel_chetaev.tex");
  nhc::write_derivation_latex(latex, scene, {chetaev});

  // Analyse: Σ-method and the consistent initial point.
  const nhc::ModelAnalysis analysis = nhc::analyze_model(scene, chetaev);
  if (!analysis.ok()) {
    for (const std::string& error : analysis.errors) std::cerr << error << "\n";
    return 1;
  }
  nhc::write_analysis_text(std::cout, scene, {analysis});

  // Emit: the index-1 system as a self-contained header (docs/generated-code.md).
  const nhc::Index1System system = nhc::reduce_to_index1(scene, chetaev);
  const nhc::GeneratedHeader header = nhc::generate_header(scene, system, {nhc::JacobianKind::sparse});
  std::ofstream(header.file_name) << header.text;
  std::printf("%s: %d states, %lld operations after CSE\n", header.file_name.c_str(), system.size(),
              header.after_cse.total());

  // The closed form at t0.
  const double k = b / a, v0 = std::hypot(1.0, 0.5);
  double z_dot = NAN, lambda = NAN;
  for (const auto& values : {analysis.initial->values, analysis.initial->leading})
    for (const nhc::InitialValue& v : values) {
      if (v.name == "z'") z_dot = v.value;
      if (v.name == "lambda1") lambda = v.value;
    }
  const bool ok = analysis.structure->index == 2 && std::abs(z_dot - k * v0) < 1e-10 &&
                  std::abs(lambda - m * g / (1 + k * k)) < 1e-10;
  std::printf("describe: index %d, z'(0) = %.12f (exact %.12f), lambda1(0) = %.12f (exact %.12f): %s\n",
              analysis.structure->index, z_dot, k * v0, lambda, m * g / (1 + k * k), ok ? "OK" : "FAIL");
  return ok ? 0 : 1;
}
