#include "nhc/scene/value.hpp"

#include <algorithm>
#include <cmath>

#include "nhc/expr/jet_space.hpp"
#include "nhc/expr/work_budget.hpp"
#include "nhc/expr/zero_test.hpp"

namespace nhc {

using GiNaC::ex;

namespace {

std::string shape_text(unsigned rows, unsigned cols) {
  if (rows == 1 && cols == 1) return "a scalar";
  if (cols == 1) return "a " + std::to_string(rows) + "-vector";
  return "a " + std::to_string(rows) + "x" + std::to_string(cols) + " matrix";
}

Value with_shape(unsigned rows, unsigned cols, std::vector<ex> entries) {
  return {rows, cols, std::move(entries), std::nullopt, std::nullopt, {}};
}

Value entrywise(const Value& a, const Value& b, int sign, const char* what) {
  if (a.rows != b.rows || a.cols != b.cols)
    throw ValueError(std::string("cannot ") + what + " " + a.describe() + " and " + b.describe());
  std::vector<ex> out(a.entries.size());
  for (std::size_t k = 0; k < out.size(); ++k) out[k] = a.entries[k] + sign * b.entries[k];
  return with_shape(a.rows, a.cols, std::move(out));
}

Value scaled(const Value& a, const ex& s) {
  std::vector<ex> out;
  out.reserve(a.entries.size());
  for (const ex& e : a.entries) out.push_back(s * e);
  return with_shape(a.rows, a.cols, std::move(out));
}

Value matrix_product(const Value& a, const Value& b) {
  if (a.cols != b.rows)
    throw ValueError("cannot multiply " + a.describe() + " by " + b.describe() + " (inner sizes differ)");
  std::vector<ex> out;
  out.reserve(a.rows * b.cols);
  for (unsigned i = 0; i < a.rows; ++i)
    for (unsigned j = 0; j < b.cols; ++j) {
      GiNaC::exvector terms;
      for (unsigned k = 0; k < a.cols; ++k) {
        const ex term = a.at(i, k) * b.at(k, j);
        if (!term.is_zero()) terms.push_back(term);
      }
      out.push_back(terms.empty() ? ex(0) : ex(GiNaC::add(terms)));
    }
  return with_shape(a.rows, b.cols, std::move(out));
}

const std::vector<ex>& require_vector(const Value& a, const char* what) {
  if (a.cols != 1 || a.rows < 2) throw ValueError(std::string(what) + " needs vectors, got " + a.describe());
  return a.entries;
}

/// The elementary rotation about axis `axis` (0 x, 1 y, 2 z); ω = angle' e_axis.
Value elementary_rotation(int axis, const ex& angle, const JetSpace& jet) {
  const ex c = GiNaC::cos(angle), s = GiNaC::sin(angle);
  std::vector<ex> m(9, ex(0));
  const int i = (axis + 1) % 3, j = (axis + 2) % 3;  // the plane the rotation turns
  m[static_cast<unsigned>(axis * 4)] = 1;
  m[static_cast<unsigned>(i * 3 + i)] = c;
  m[static_cast<unsigned>(j * 3 + j)] = c;
  m[static_cast<unsigned>(i * 3 + j)] = -s;
  m[static_cast<unsigned>(j * 3 + i)] = s;
  Value r = with_shape(3, 3, std::move(m));
  std::vector<ex> w(3, ex(0));
  w[static_cast<unsigned>(axis)] = jet.total_derivative(angle);
  r.angular_velocity = w;
  r.body_angular_velocity = std::move(w);
  r.factors = {{axis, angle}};
  return r;
}

/// The Euler angles r is a product of (value.hpp), if it is: its factors without the leading and
/// trailing ones that turn by no coordinate (a constant rotation before the chain turns ω, one
/// after it leaves ω alone: neither changes the rank of the rates' map), when three remain, each
/// about a different coordinate q or −q, consecutive axes different.
std::optional<EulerChain> euler_chain(const Value& r, const JetSpace& jet) {
  const auto& f = r.factors;
  const auto turns = [&](std::size_t k) { return jet.highest_coordinate_order(f[k].second) >= 0; };
  std::size_t begin = 0, end = f.size();
  while (begin < end && !turns(begin)) ++begin;
  while (end > begin && !turns(end - 1)) --end;
  if (end - begin != 3) return std::nullopt;
  EulerChain chain;
  std::vector<int> axes, coordinates;
  for (std::size_t k = begin; k < end; ++k) {
    std::optional<JetCoordinate> c = jet.classify(f[k].second);
    if (!c) c = jet.classify(-f[k].second);
    if (!c || c->kind != VariableKind::coordinate || c->order != 0) return std::nullopt;
    if (std::find(coordinates.begin(), coordinates.end(), c->index) != coordinates.end()) return std::nullopt;
    coordinates.push_back(c->index);
    axes.push_back(f[k].first);
    chain.angles.push_back(jet.coordinates()[static_cast<std::size_t>(c->index)]);
  }
  if (axes[0] == axes[1] || axes[1] == axes[2]) return std::nullopt;
  const char* const axis_names = "xyz";
  for (std::size_t k = 0; k < 3; ++k) chain.axes += std::string(k ? "-" : "") + axis_names[axes[k]];
  // det[e_a, e_b, R_b(q2) e_c]: R_b(q2) e_a = cos q2 e_a ± sin q2 (e_b × e_a) gives ± sin q2;
  // R_b(q2) e_c with c the third axis, cos q2 e_c ± sin q2 e_a, gives ± cos q2.
  const ex middle = jet.q(coordinates[1], 0);
  const bool proper = axes[0] == axes[2];
  chain.determinant = proper ? GiNaC::sin(middle) : GiNaC::cos(middle);
  chain.zeros = proper ? "0, pi" : "-pi/2, pi/2";
  return chain;
}

/// Adds the Euler angles r is made of, if any, to check's list (once).
void note_euler_chain(const Value& r, const JetSpace& jet, const RotationCheck& check) {
  if (!check.euler_chains) return;
  if (std::optional<EulerChain> chain = euler_chain(r, jet))
    if (std::find(check.euler_chains->begin(), check.euler_chains->end(), *chain) == check.euler_chains->end())
      check.euler_chains->push_back(std::move(*chain));
}

}  // namespace

void require_rotation(const Value& r, const RotationCheck& check, const char* what) {
  if (!r.is_square3()) throw ValueError(std::string(what) + " needs a 3x3 rotation matrix, got " + r.describe());
  const Value product = matrix_product(r, transpose(r));
  static const GiNaC::exmap empty;
  for (unsigned i = 0; i < 3; ++i)
    for (unsigned j = 0; j < 3; ++j) {
      const ex deviation = product.at(i, j) - (i == j ? 1 : 0);
      if (work_budget::is_zero(deviation)) continue;
      bool zero = false;
      try {
        zero = vanishes_at_sample_points(deviation, check.point ? *check.point : empty);
      } catch (const std::exception&) {
        zero = false;
      }
      if (!zero)
        throw ValueError(std::string(what) +
                         " needs a rotation matrix: R*transpose(R) is not "
                         "the identity (entry " +
                         std::to_string(i + 1) + ", " + std::to_string(j + 1) + ", at the initial point)");
    }
}

Value Value::vector(std::vector<ex> entries) {
  const auto n = static_cast<unsigned>(entries.size());
  return with_shape(n, 1, std::move(entries));
}

Value Value::matrix(unsigned rows, unsigned cols, std::vector<ex> entries) {
  return with_shape(rows, cols, std::move(entries));
}

std::string Value::describe() const { return shape_text(rows, cols); }

Value operator-(const Value& a) { return scaled(a, -1); }
Value add(const Value& a, const Value& b) { return entrywise(a, b, 1, "add"); }
Value subtract(const Value& a, const Value& b) { return entrywise(a, b, -1, "subtract"); }

Value multiply(const Value& a, const Value& b) {
  if (a.is_scalar()) return scaled(b, a.entries[0]);
  if (b.is_scalar()) return scaled(a, b.entries[0]);
  if (a.cols == 1 && b.cols == 1)
    throw ValueError("cannot multiply " + a.describe() + " by " + b.describe() + ": use dot(a, b) or cross(a, b)");
  Value product = matrix_product(a, b);
  if (a.angular_velocity && b.angular_velocity && product.is_square3()) {
    // ω(R₁R₂) = ω(R₁) + R₁ ω(R₂)
    const Value rotated = matrix_product(a, Value::vector(*b.angular_velocity));
    std::vector<ex> w(3);
    for (unsigned k = 0; k < 3; ++k) w[k] = (*a.angular_velocity)[k] + rotated.entries[k];
    product.angular_velocity = std::move(w);
    // Ω(R₁R₂) = R₂ᵀ Ω(R₁) + Ω(R₂)
    const Value turned =
        matrix_product(transpose(Value::matrix(3, 3, b.entries)), Value::vector(*a.body_angular_velocity));
    std::vector<ex> body(3);
    for (unsigned k = 0; k < 3; ++k) body[k] = turned.entries[k] + (*b.body_angular_velocity)[k];
    product.body_angular_velocity = std::move(body);
    if (!a.factors.empty() && !b.factors.empty()) {
      product.factors = a.factors;
      product.factors.insert(product.factors.end(), b.factors.begin(), b.factors.end());
    }
  }
  return product;
}

Value transpose(const Value& a) {
  std::vector<ex> out(a.entries.size());
  for (unsigned i = 0; i < a.rows; ++i)
    for (unsigned j = 0; j < a.cols; ++j) out[j * a.rows + i] = a.at(i, j);
  Value t = with_shape(a.cols, a.rows, std::move(out));
  if (a.angular_velocity) {
    // ω(Rᵀ) = −Ω(R), Ω(Rᵀ) = −ω(R)
    t.angular_velocity = (-Value::vector(*a.body_angular_velocity)).entries;
    t.body_angular_velocity = (-Value::vector(*a.angular_velocity)).entries;
    // (R₁R₂)ᵀ = R₂ᵀR₁ᵀ, R_a(θ)ᵀ = R_a(−θ)
    for (auto it = a.factors.rbegin(); it != a.factors.rend(); ++it) t.factors.emplace_back(it->first, -it->second);
  }
  return t;
}

Value component(const Value& a, const std::vector<long>& indices) {
  auto check = [](long index, unsigned size, const char* what) {
    if (index < 1 || index > static_cast<long>(size))
      throw ValueError(std::string(what) + " index " + std::to_string(index) + " is out of range 1.." +
                       std::to_string(size));
    return static_cast<unsigned>(index - 1);
  };
  if (a.is_scalar()) throw ValueError("a scalar cannot be indexed");
  if (indices.size() == 1) {
    if (a.cols != 1 && a.rows != 1) throw ValueError("a matrix takes two indices, M[i, j]; got one");
    const unsigned size = a.cols == 1 ? a.rows : a.cols;
    return Value::scalar(a.entries[check(indices[0], size, "vector")]);
  }
  if (indices.size() == 2)
    return Value::scalar(a.at(check(indices[0], a.rows, "row"), check(indices[1], a.cols, "column")));
  throw ValueError("at most two indices, M[i, j]");
}

ex dot(const Value& a, const Value& b) {
  const auto& x = require_vector(a, "dot");
  const auto& y = require_vector(b, "dot");
  if (x.size() != y.size()) throw ValueError("dot of " + a.describe() + " and " + b.describe() + ": lengths differ");
  GiNaC::exvector terms;
  for (std::size_t k = 0; k < x.size(); ++k) terms.push_back(x[k] * y[k]);
  return GiNaC::add(terms);
}

Value cross(const Value& a, const Value& b) {
  const auto& x = require_vector(a, "cross");
  const auto& y = require_vector(b, "cross");
  if (x.size() != 3 || y.size() != 3)
    throw ValueError("cross needs two 3-vectors, got " + a.describe() + " and " + b.describe());
  return Value::vector({x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]});
}

ex norm(const Value& a) {
  require_vector(a, "norm");
  return GiNaC::sqrt(dot(a, a));
}

Value total_derivative(const Value& a, const JetSpace& jet, int k) {
  std::vector<ex> out = a.entries;
  for (ex& e : out)
    for (int j = 0; j < k; ++j) e = jet.total_derivative(e);
  return with_shape(a.rows, a.cols, std::move(out));
}

Value rotation_x(const ex& angle, const JetSpace& jet) { return elementary_rotation(0, angle, jet); }
Value rotation_y(const ex& angle, const JetSpace& jet) { return elementary_rotation(1, angle, jet); }
Value rotation_z(const ex& angle, const JetSpace& jet) { return elementary_rotation(2, angle, jet); }

Value rotation_of_quaternion(const std::vector<ex>& q, const JetSpace& jet) {
  if (q.size() != 4) throw ValueError("quat takes the 4 components of a quaternion, scalar first");
  const ex& s = q[0];
  const std::vector<ex> v = {q[1], q[2], q[3]};
  const ex diagonal = s * s - (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  std::vector<ex> m(9);
  for (unsigned i = 0; i < 3; ++i)
    for (unsigned j = 0; j < 3; ++j) m[i * 3 + j] = (i == j ? diagonal : ex(0)) + 2 * v[i] * v[j];
  // 2 q0 [v]×: [v]× = [[0, -v3, v2], [v3, 0, -v1], [-v2, v1, 0]]
  m[1] -= 2 * s * v[2], m[2] += 2 * s * v[1];
  m[3] += 2 * s * v[2], m[5] -= 2 * s * v[0];
  m[6] -= 2 * s * v[1], m[7] += 2 * s * v[0];
  Value r = with_shape(3, 3, std::move(m));
  const ex ds = jet.total_derivative(s);
  std::vector<ex> dv(3);
  for (unsigned k = 0; k < 3; ++k) dv[k] = jet.total_derivative(v[k]);
  const Value turn = cross(Value::vector(v), Value::vector(dv));  // v × v'
  std::vector<ex> w(3), body(3);
  for (unsigned k = 0; k < 3; ++k) {
    const ex common = s * dv[k] - ds * v[k];
    w[k] = 2 * (common + turn.entries[k]);
    body[k] = 2 * (common - turn.entries[k]);
  }
  r.angular_velocity = std::move(w);
  r.body_angular_velocity = std::move(body);
  return r;
}

Value spatial_angular_velocity(const Value& r, const JetSpace& jet, const RotationCheck& check) {
  note_euler_chain(r, jet, check);
  if (r.angular_velocity) return Value::vector(*r.angular_velocity);
  require_rotation(r, check, "omega");
  // Ṙ Rᵀ = [ω]×: ω from its skew-symmetric part, ω_x = (W₃₂ − W₂₃)/2 and cyclically.
  const Value w = matrix_product(total_derivative(r, jet, 1), transpose(r));
  return Value::vector({(w.at(2, 1) - w.at(1, 2)) / 2, (w.at(0, 2) - w.at(2, 0)) / 2, (w.at(1, 0) - w.at(0, 1)) / 2});
}

Value body_angular_velocity(const Value& r, const JetSpace& jet, const RotationCheck& check) {
  note_euler_chain(r, jet, check);
  if (r.body_angular_velocity) return Value::vector(*r.body_angular_velocity);
  require_rotation(r, check, "omega_body");
  // Ω = Rᵀ ω (Rᵀ Ṙ = Rᵀ [ω]× R = [Rᵀ ω]×)
  return matrix_product(transpose(Value::matrix(3, 3, r.entries)), spatial_angular_velocity(r, jet, check));
}

}  // namespace nhc
