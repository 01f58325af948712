#pragma once
/// \file derivation_emitters.hpp
/// \brief Writing derived models for people (text, LaTeX) and tools (JSON).
/// Implementations: text_emitter.cpp, latex_emitter.cpp, json_emitter.cpp.

#include <ostream>
#include <string>
#include <vector>

#include "nhc/derive/models.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc {

/// The named intermediates (kept definitions and the derivatives made from them,
/// docs/intermediates.md) that the printed expressions use, each after the ones it uses: the
/// "where" list that follows the equations, as a textbook writes it. Empty when the scene was
/// read with its definitions substituted (`nhc derive --expand`).
std::vector<GiNaC::ex> derivation_intermediates(const Scene& scene, const std::vector<DerivedModel>& models);

/// Plain text: per model its residuals R_i = 0 and constraints, in GiNaC syntax, then the
/// intermediates they use ("where d = …").
void write_derivation_text(std::ostream& out, const Scene& scene, const std::vector<DerivedModel>& models);
/// A standalone amsmath document, one aligned block per model; compiles with pdflatex.
void write_derivation_latex(std::ostream& out, const Scene& scene, const std::vector<DerivedModel>& models);
/// The same equations as math only (align* blocks with their headings as \text rows), for
/// MathJax: Jupyter's _repr_latex_ and `nhc derive --format latex-math`.
void write_derivation_latex_math(std::ostream& out, const Scene& scene, const std::vector<DerivedModel>& models);
/// `lhs &= e` as the documents print an equation: an align* environment whose rows break a long
/// expression between its terms and factors (continued rows start `&\quad`).
void write_latex_equation(std::ostream& out, const std::string& lhs, const GiNaC::ex& e);
/// {"scene", "parameters", "symbols", "definitions", "models"} as documented in README.md;
/// "definitions" lists the intermediates in dependency order, so that a reader substitutes them
/// from the last to the first.
void write_derivation_json(std::ostream& out, const Scene& scene, const std::vector<DerivedModel>& models);

}  // namespace nhc
