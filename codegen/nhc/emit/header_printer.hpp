#pragma once
/// \file header_printer.hpp
/// \brief The printing half of the header emitter: a PreparedModel (model_preparation.hpp) as
/// the text of the self-contained header of docs/generated-code.md, one function per section.

#include <string>

#include "nhc/analysis/index1_system.hpp"
#include "nhc/emit/model_preparation.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc {

/// The most translation units a generated header can be compiled as (docs/generated-code.md):
/// compiled with NHC_PARTS = K (1 .. this) and NHC_PART = k (0 .. K-1), part k defines only its
/// share of the functions, part 0 the table; the K objects linked together are the model.
inline constexpr int kMaxTranslationUnits = 4;

/// The banner line that says so, followed by kMaxTranslationUnits (nhc::jit looks for it).
inline constexpr const char* kTranslationUnitsBanner = "// Compiles as NHC_PARTS = 1 to ";

/// The header's text: banner, the C table's definition (model_table.h), metadata, the
/// Jacobian's structure, the functions, the table filled by field name and its entry point.
/// With at least `split_from_bytes` of functions, also the NHC_PART protocol (and its banner
/// line), so that nhc::jit may compile it as several translation units.
std::string print_header(const Scene& scene, const Index1System& system, const PreparedModel& model,
                         std::size_t split_from_bytes);

}  // namespace nhc
