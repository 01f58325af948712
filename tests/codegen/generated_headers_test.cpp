// The generated headers compiled into this binary (CMakeLists.txt), checked at random points
// against independent paths (Pinocchio's cppadcg tests do the same): GiNaC's own evaluation of
// the symbolic index-1 system, GiNaC's symbolic derivatives, central finite differences of the
// compiled residual, and the dense against the sparse Jacobian.
#include <catch2/catch.hpp>
#include <ginac/ginac.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "compiled_headers.hpp"
#include "nhc/emit/model_table_text.hpp"
#include "nhc/analysis/index1_reduction.hpp"
#include "nhc/derive/models.hpp"
#include "nhc/emit/header_emitter.hpp"
#include "nhc/scene/scene.hpp"

namespace {

using GiNaC::ex;

/// The symbolic side of one compiled header.
struct Symbolic {
  nhc::Scene scene;
  nhc::Index1System system;
};

const Symbolic& symbolic(const std::string& scene_file, const std::string& model) {
  static std::map<std::string, Symbolic> cache;
  const std::string key = scene_file + "/" + model;
  auto it = cache.find(key);
  if (it == cache.end()) {
    Symbolic s{nhc::load_scene(std::string(NHC_SOURCE_DIR) + "/" + scene_file), {}};
    s.system = nhc::reduce_to_index1(s.scene, nhc::derive_model(s.scene, *nhc::parse_model_kind(model)));
    it = cache.emplace(key, std::move(s)).first;
  }
  return it->second;
}

/// One random evaluation point.
struct Point {
  double t = 0;
  std::vector<double> y, yp, p;
  double cj = 0;
};

Point random_point(const nhc_model_table& table, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Point x;
  x.t = 0.5 + 0.5 * u(rng);
  for (int k = 0; k < table.n_states; ++k) {
    x.y.push_back(u(rng));
    x.yp.push_back(u(rng));
  }
  for (int k = 0; k < table.n_parameters; ++k)
    x.p.push_back(table.default_parameters[k] * (1.0 + 0.2 * u(rng)) + 0.1 * u(rng));
  x.cj = 10.0 * (1.5 + u(rng));
  return x;
}

double evaluate(const ex& e, const nhc::Index1System& system, const Point& x, const GiNaC::realsymbol* cj = nullptr) {
  GiNaC::exmap values;
  values[system.jet->time()] = x.t;
  for (size_t k = 0; k < x.p.size(); ++k) values[system.jet->parameter(static_cast<int>(k))] = x.p[k];
  for (size_t k = 0; k < x.y.size(); ++k) {
    values[system.y[k]] = x.y[k];
    values[system.yp[k]] = x.yp[k];
  }
  if (cj) values[*cj] = x.cj;
  const ex v = e.subs(values).evalf();
  REQUIRE(GiNaC::is_a<GiNaC::numeric>(v));
  REQUIRE(GiNaC::ex_to<GiNaC::numeric>(v).is_real());
  return GiNaC::ex_to<GiNaC::numeric>(v).to_double();
}

/// |a − b| ≤ tol · max(1, |b|).
bool close(double a, double b, double tol) {
  return std::isfinite(a) && std::fabs(a - b) <= tol * std::max(1.0, std::fabs(b));
}

std::vector<double> residual(const nhc_model_table& table, const Point& x, const std::vector<double>& y,
                             const std::vector<double>& yp) {
  std::vector<double> r(static_cast<size_t>(table.n_states));
  table.residual(x.t, y.data(), yp.data(), x.p.data(), r.data());
  return r;
}

/// The iteration matrix as a dense column-major array, from whichever flavour the table has.
std::vector<double> dense_jacobian(const nhc_model_table& table, const Point& x) {
  const int n = table.n_states;
  std::vector<double> J(static_cast<size_t>(n * n), 0.0);
  if (table.jacobian) {
    table.jacobian(x.t, x.y.data(), x.yp.data(), x.cj, x.p.data(), J.data());
  } else {
    std::vector<double> values(static_cast<size_t>(std::max(table.jacobian_nnz, 1)));
    table.jacobian_values(x.t, x.y.data(), x.yp.data(), x.cj, x.p.data(), values.data());
    for (int j = 0; j < n; ++j)
      for (int k = table.jacobian_colptr[j]; k < table.jacobian_colptr[j + 1]; ++k)
        J[static_cast<size_t>(table.jacobian_rowind[k] + j * n)] = values[static_cast<size_t>(k)];
  }
  return J;
}

constexpr int kPoints = 25;

}  // namespace

TEST_CASE("every compiled header matches its symbolic index-1 system", "[codegen]") {
  REQUIRE(!nhc_test::compiled_headers().empty());
  for (const auto& compiled : nhc_test::compiled_headers()) {
    const std::string label = std::string(compiled.scene) + " " + compiled.model + " " + compiled.jacobian;
    SECTION(label) {
      const nhc_model_table& table = *compiled.table();
      const Symbolic& s = symbolic(compiled.scene_file, compiled.model);
      const nhc::Index1System& system = s.system;
      const int n = system.size();

      // Metadata.
      REQUIRE(table.abi_version == nhc::kModelTableAbiVersion);
      // Sensitivity additions only with HeaderOptions::sensitivities (not asked for here).
      CHECK(table.residual_parameter_jacobian == nullptr);
      CHECK(table.hidden_parameter_jacobian == nullptr);
      CHECK(std::string(table.scene_name) == compiled.scene);
      CHECK(std::string(table.model_name) == compiled.model);
      REQUIRE(table.n_states == n);
      CHECK(table.n_coordinates == s.scene.coordinate_count());
      CHECK(table.n_parameters == static_cast<int>(s.scene.parameter_values.size()));
      REQUIRE(table.n_hidden == static_cast<int>(system.hidden_constraints.size()));
      CHECK(table.n_invariants == static_cast<int>(s.scene.invariants.size()));
      CHECK(table.n_reference == static_cast<int>(s.scene.reference.for_model(system.model).size()));
      for (int k = 0; k < n; ++k) {
        const nhc::StateComponent& state = system.states[static_cast<size_t>(k)];
        CHECK(std::string(table.state_names[k]) == state.name);
        CHECK(table.state_order[k] == state.order);
        CHECK(table.differential_id[k] == (state.differential ? 1.0 : 0.0));
        CHECK(table.state_variable[k] ==
              (state.kind == nhc::VariableKind::coordinate ? state.index : table.n_coordinates + state.index));
        CHECK(std::string(table.residual_names[k]) == system.residual_names[static_cast<size_t>(k)]);
      }
      for (int k = 0; k < table.n_parameters; ++k) {
        CHECK(std::string(table.parameter_names[k]) == s.scene.jet->parameters()[static_cast<size_t>(k)]);
        CHECK(table.default_parameters[k] == s.scene.parameter_values[static_cast<size_t>(k)]);
      }
      for (int k = 0; k < table.n_hidden; ++k)
        CHECK(std::string(table.hidden_names[k]) == system.hidden_constraint_names[static_cast<size_t>(k)]);
      const bool dense = std::string(compiled.jacobian) == "dense";
      CHECK((table.jacobian != nullptr) == dense);
      CHECK((table.jacobian_values != nullptr) == !dense);
      CHECK((table.hidden_constraints != nullptr) == (table.n_hidden > 0));
      CHECK((table.invariants != nullptr) == (table.n_invariants > 0));
      CHECK((table.reference != nullptr) == (table.n_reference > 0));
      CHECK((table.singular_quantities != nullptr) == (table.n_singular > 0));

      const nhc::SymbolicJacobian jac = nhc::index1_jacobian(system);
      if (!dense) {
        // The sparsity pattern is exactly the symbolic nonzeros, sorted within each column.
        REQUIRE(table.jacobian_nnz == static_cast<int>(jac.rowind.size()));
        for (int j = 0; j <= n; ++j) CHECK(table.jacobian_colptr[j] == jac.colptr[static_cast<size_t>(j)]);
        for (int k = 0; k < table.jacobian_nnz; ++k)
          CHECK(table.jacobian_rowind[k] == jac.rowind[static_cast<size_t>(k)]);
      }

      // Independent symbolic derivatives, computed here rather than taken from the emitter.
      GiNaC::realsymbol cj("cj");
      std::vector<ex> dFdy, dFdyp;
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          dFdy.push_back(system.residuals[static_cast<size_t>(i)].diff(system.y[static_cast<size_t>(j)]));
          dFdyp.push_back(system.residuals[static_cast<size_t>(i)].diff(system.yp[static_cast<size_t>(j)]));
        }
      const std::vector<nhc::ModelInvariant> invariants = nhc::invariants_in_states(s.scene, system);
      std::vector<nhc::SingularQuantity> singular = nhc::singular_quantities(system);
      for (nhc::SingularQuantity& q : nhc::euler_angle_monitors(s.scene, system)) singular.push_back(std::move(q));
      REQUIRE(table.n_singular == static_cast<int>(singular.size()));

      std::mt19937_64 rng(20261121);
      for (int sample = 0; sample < kPoints; ++sample) {
        const Point x = random_point(table, rng);
        INFO("sample " << sample);

        // Residual against GiNaC's evaluation of the same expressions.
        const std::vector<double> r = residual(table, x, x.y, x.yp);
        for (int i = 0; i < n; ++i) {
          const double expected = evaluate(system.residuals[static_cast<size_t>(i)], system, x);
          INFO("residual " << i << ": " << r[static_cast<size_t>(i)] << " vs " << expected);
          CHECK(close(r[static_cast<size_t>(i)], expected, 1e-12));
        }

        // Jacobian against GiNaC's symbolic derivative and central finite differences.
        const std::vector<double> J = dense_jacobian(table, x);
        for (int j = 0; j < n; ++j) {
          const double hy = 1e-6 * (1.0 + std::fabs(x.y[static_cast<size_t>(j)]));
          const double hyp = 1e-6 * (1.0 + std::fabs(x.yp[static_cast<size_t>(j)]));
          std::vector<double> y_plus = x.y, y_minus = x.y, yp_plus = x.yp, yp_minus = x.yp;
          y_plus[static_cast<size_t>(j)] += hy;
          y_minus[static_cast<size_t>(j)] -= hy;
          yp_plus[static_cast<size_t>(j)] += hyp;
          yp_minus[static_cast<size_t>(j)] -= hyp;
          const auto ry_plus = residual(table, x, y_plus, x.yp), ry_minus = residual(table, x, y_minus, x.yp);
          const auto rp_plus = residual(table, x, x.y, yp_plus), rp_minus = residual(table, x, x.y, yp_minus);
          for (int i = 0; i < n; ++i) {
            const size_t at = static_cast<size_t>(i + j * n);
            const double symbolic_value = evaluate(dFdy[at], system, x) + x.cj * evaluate(dFdyp[at], system, x);
            const double fd = (ry_plus[static_cast<size_t>(i)] - ry_minus[static_cast<size_t>(i)]) / (2 * hy) +
                              x.cj * (rp_plus[static_cast<size_t>(i)] - rp_minus[static_cast<size_t>(i)]) / (2 * hyp);
            INFO("J(" << i << ", " << j << ") = " << J[at] << ", GiNaC " << symbolic_value << ", FD " << fd);
            CHECK(close(J[at], symbolic_value, 1e-12));
            CHECK(close(J[at], fd, 1e-5));
          }
        }

        // Hidden constraints and their Jacobian.
        if (table.n_hidden > 0) {
          const int h = table.n_hidden;
          std::vector<double> g(static_cast<size_t>(h)), G(static_cast<size_t>(h * n));
          table.hidden_constraints(x.t, x.y.data(), x.p.data(), g.data());
          table.hidden_constraints_jacobian(x.t, x.y.data(), x.p.data(), G.data());
          for (int i = 0; i < h; ++i) {
            const ex& gi = system.hidden_constraints[static_cast<size_t>(i)];
            CHECK(close(g[static_cast<size_t>(i)], evaluate(gi, system, x), 1e-12));
            for (int j = 0; j < n; ++j) {
              const double expected = evaluate(gi.diff(system.y[static_cast<size_t>(j)]), system, x);
              INFO("G(" << i << ", " << j << ")");
              CHECK(close(G[static_cast<size_t>(i + j * h)], expected, 1e-12));
              // The reduction's own dg/dy, when it provides one.
              if (static_cast<size_t>(i) < system.hidden_constraint_jacobian.size())
                CHECK(close(G[static_cast<size_t>(i + j * h)],
                            evaluate(system.hidden_constraint_derivative(static_cast<size_t>(i), j), system, x),
                            1e-12));
            }
          }
        }

        if (table.n_invariants > 0) {
          std::vector<double> out(static_cast<size_t>(table.n_invariants));
          table.invariants(x.t, x.y.data(), x.yp.data(), x.p.data(), out.data());
          for (int i = 0; i < table.n_invariants; ++i)
            CHECK(close(out[static_cast<size_t>(i)], evaluate(invariants[static_cast<size_t>(i)].in_states, system, x),
                        1e-12));
        }

        if (table.n_reference > 0) {
          std::vector<double> q(static_cast<size_t>(table.n_reference));
          table.reference(x.t, x.p.data(), q.data());
          const nhc::SceneReference::Entries reference = s.scene.reference.for_model(system.model);
          for (int i = 0; i < table.n_reference; ++i) {
            CHECK(table.reference_coordinate[i] == reference[static_cast<size_t>(i)].first);
            CHECK(
                close(q[static_cast<size_t>(i)], evaluate(reference[static_cast<size_t>(i)].second, system, x), 1e-12));
          }
        }

        if (table.n_singular > 0) {
          std::vector<double> out(static_cast<size_t>(table.n_singular));
          table.singular_quantities(x.t, x.y.data(), x.p.data(), out.data());
          for (int i = 0; i < table.n_singular; ++i)
            CHECK(close(out[static_cast<size_t>(i)], evaluate(singular[static_cast<size_t>(i)].expression, system, x),
                        1e-12));
        }
      }
    }
  }
}

TEST_CASE("sparse Jacobian values equal the dense Jacobian", "[codegen]") {
  const auto& all = nhc_test::compiled_headers();
  int pairs = 0;
  for (const auto& sparse : all) {
    if (std::string(sparse.jacobian) != "sparse") continue;
    const auto dense = std::find_if(all.begin(), all.end(), [&](const nhc_test::CompiledHeader& h) {
      return std::string(h.jacobian) == "dense" && std::string(h.scene) == sparse.scene &&
             std::string(h.model) == sparse.model;
    });
    REQUIRE(dense != all.end());
    ++pairs;
    const nhc_model_table& S = *sparse.table();
    const nhc_model_table& D = *dense->table();
    const int n = S.n_states;
    std::mt19937_64 rng(7);
    for (int sample = 0; sample < kPoints; ++sample) {
      const Point x = random_point(S, rng);
      std::vector<double> J(static_cast<size_t>(n * n));
      D.jacobian(x.t, x.y.data(), x.yp.data(), x.cj, x.p.data(), J.data());
      std::vector<double> values(static_cast<size_t>(std::max(S.jacobian_nnz, 1)));
      S.jacobian_values(x.t, x.y.data(), x.yp.data(), x.cj, x.p.data(), values.data());
      std::vector<char> in_pattern(static_cast<size_t>(n * n), 0);
      for (int j = 0; j < n; ++j)
        for (int k = S.jacobian_colptr[j]; k < S.jacobian_colptr[j + 1]; ++k) {
          const size_t at = static_cast<size_t>(S.jacobian_rowind[k] + j * n);
          in_pattern[at] = 1;
          CHECK(close(values[static_cast<size_t>(k)], J[at], 1e-15));
        }
      for (size_t at = 0; at < J.size(); ++at)
        if (!in_pattern[at]) CHECK(J[at] == 0.0);
    }
  }
  CHECK(pairs > 0);
}
