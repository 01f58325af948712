#pragma once
/// \file codegen.hpp
/// \brief The nhc front end as a library (CMake target nhc::codegen), one header for the
/// whole pipeline: scene → derivation → structural analysis → index-1 system → emitters.
/// Walk-through: docs/library.md.
///
///   nhc::Scene          load_scene("file.toml"), parse_scene(text, path), SceneBuilder
///   nhc::DerivedModel   derive_model(scene, ModelKind::chetaev)
///   nhc::ModelAnalysis  analyze_model(scene, derived)            (Σ-method, consistent t0 point)
///   nhc::Index1System   reduce_to_index1(scene, derived)
///   emitters            write_derivation_text/latex/json, write_analysis_text/json,
///                       generate_header(scene, system, options)  (docs/generated-code.md)
/// Failures: InputError (bad scene), MathError (singular system, model not applicable).

#include "nhc/analysis/index1_reduction.hpp"
#include "nhc/analysis/model_analysis.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/emit/analysis_emitters.hpp"
#include "nhc/emit/derivation_emitters.hpp"
#include "nhc/emit/header_emitter.hpp"
#include "nhc/errors.hpp"
#include "nhc/scene/scene.hpp"
#include "nhc/scene/scene_builder.hpp"
