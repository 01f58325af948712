#pragma once
/// \file derivation_emitters.hpp
/// \brief Writing derived models for people (text, LaTeX) and tools (JSON).
/// Implementations: text_emitter.cpp, latex_emitter.cpp, json_emitter.cpp.

#include <ostream>
#include <vector>

#include "nhc/derive/models.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc {

/// Plain text: per model its residuals R_i = 0 and constraints, in GiNaC syntax.
void write_derivation_text(std::ostream& out, const Scene& scene,
                           const std::vector<DerivedModel>& models);
/// A standalone amsmath document, one aligned block per model; compiles with pdflatex.
void write_derivation_latex(std::ostream& out, const Scene& scene,
                            const std::vector<DerivedModel>& models);
/// {"scene", "parameters", "symbols", "models"} as documented in README.md.
void write_derivation_json(std::ostream& out, const Scene& scene,
                           const std::vector<DerivedModel>& models);

}  // namespace nhc
