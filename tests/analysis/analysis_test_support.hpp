#pragma once
// Shared helpers of the [sigma] tests: loading scenes, numeric evaluation with GiNaC.
#include <ginac/ginac.h>

#include <Eigen/Dense>

#include <string>
#include <vector>

#include "nhc/analysis/dae_system.hpp"
#include "nhc/analysis/structural_analysis.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/scene/scene.hpp"

namespace nhc::test {

inline Scene scene_at(const std::string& relative) { return load_scene(std::string(NHC_SOURCE_DIR) + "/" + relative); }

inline StructuralAnalysis structure_of(const Scene& scene, ModelKind kind) {
  return analyze_structure(dae_system_of(scene, derive_model(scene, kind)));
}

/// e at the point, by GiNaC's evalf; the test fails on anything but a real number.
inline double eval(const GiNaC::ex& e, const GiNaC::exmap& point) {
  const GiNaC::ex v = e.subs(point, GiNaC::subs_options::no_pattern).evalf();
  if (!GiNaC::is_a<GiNaC::numeric>(v) || !GiNaC::ex_to<GiNaC::numeric>(v).is_real())
    throw std::runtime_error("not a real number");
  return GiNaC::ex_to<GiNaC::numeric>(v).to_double();
}

inline double smallest_singular_value(const Eigen::MatrixXd& m) {
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(m);
  return svd.singularValues()(svd.singularValues().size() - 1);
}

inline double cond(const Eigen::MatrixXd& m) {
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(m);
  const auto& s = svd.singularValues();
  return s(0) / s(s.size() - 1);
}

}  // namespace nhc::test
