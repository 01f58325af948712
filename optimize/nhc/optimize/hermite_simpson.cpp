#include "nhc/optimize/hermite_simpson.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace nhc::optimize {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;
/// The amplitude of the straight line's bend (straight_line()).
constexpr double kBend = 1e-2;

/// Simpson's weight of point j within its interval, in units of the interval's length h:
/// 1/6 at each end of every interval (a node inside the mesh ends two), 4/6 at a midpoint.
double simpson_weight(int point, int points) {
  if (point % 2 == 1) return 4.0 / 6.0;
  return point == 0 || point == points - 1 ? 1.0 / 6.0 : 2.0 / 6.0;
}

}  // namespace

HermiteSimpson::HermiteSimpson(const Scene& scene, const Settings& settings, int intervals)
    : n_(scene.coordinate_count()),
      m_(scene.constraint_count()),
      n_intervals_(intervals),
      t0_(scene.initial.t0),
      t_end_low_(settings.t_end_low),
      t_end_high_(settings.t_end_high),
      free_time_(settings.free_time()),
      functions_(scene, settings),
      coordinate_names_(scene.jet->coordinates()) {
  low_.assign(static_cast<std::size_t>(variables()), -kInfinity);
  high_.assign(static_cast<std::size_t>(variables()), kInfinity);
  auto index = [&](const PathQuantity& q, int point, const SourceLocation& where) {
    if (q.kind == PathQuantity::Kind::input)
      throw InputError(where, "'" + q.name + "' is an input: nhc optimize so far solves scenes without [inputs] "
                                             "(the vakonomic problem: docs/optimize.md, \"Scope\")");
    if (q.order > 1)
      throw InputError(where, "'" + q.name + "': the transcription holds coordinates and their first derivatives only");
    return q.order == 0 ? q_index(point, q.index) : v_index(point, q.index);
  };
  for (const PathBound& b : settings.bounds)
    for (int j = 0; j < points(); ++j) {
      const auto k = static_cast<std::size_t>(index(b.quantity, j, b.where));
      low_[k] = std::max(low_[k], b.low);
      high_[k] = std::min(high_[k], b.high);
    }
  auto fix = [&](const std::vector<BoundaryValue>& values, int point, const char* table) {
    for (const BoundaryValue& b : values) {
      const auto k = static_cast<std::size_t>(index(b.quantity, point, b.where));
      if (b.value < low_[k] || b.value > high_[k])
        throw InputError(b.where, fmt::format("{} = {} in [optimize.{}] is outside its bound [{}, {}] in [optimize.bounds]",
                                              b.quantity.name, b.value, table, low_[k], high_[k]));
      low_[k] = high_[k] = b.value;
    }
  };
  fix(settings.initial, 0, "initial");
  fix(settings.final, points() - 1, "final");
  if (free_time_) {
    low_.back() = t_end_low_;
    high_.back() = t_end_high_;
  }
}

int HermiteSimpson::jacobian_nonzeros() const noexcept {
  const int t = free_time_ ? 1 : 0;
  return n_intervals_ * 2 * n_ * (5 + t) + points() * m_ * (2 * n_ + t);
}

double HermiteSimpson::time(int point, const double* z) const noexcept {
  return t0_ + (final_time(z) - t0_) * point / (2.0 * n_intervals_);
}

void HermiteSimpson::variable_bounds(double* low, double* high) const {
  std::copy(low_.begin(), low_.end(), low);
  std::copy(high_.begin(), high_.end(), high);
}

void HermiteSimpson::evaluate_points(const double* z) {
  const auto size = static_cast<std::size_t>(variables());
  if (cached_.size() == size && std::memcmp(cached_.data(), z, size * sizeof(double)) == 0) return;
  cached_.assign(z, z + size);
  at_.resize(static_cast<std::size_t>(points()));
  for (int j = 0; j < points(); ++j) {
    functions_.evaluate(time(j, z), z + q_index(j, 0), z + v_index(j, 0));
    std::vector<ValueGradient>& here = at_[static_cast<std::size_t>(j)];
    here.clear();
    here.push_back(functions_.integrand());
    for (int a = 0; a < m_; ++a) here.push_back(functions_.constraint(a));
    here.push_back(functions_.final_cost());
  }
}

double HermiteSimpson::objective(const double* z) {
  evaluate_points(z);
  const double h = (final_time(z) - t0_) / n_intervals_;
  double sum = 0;
  for (int j = 0; j < points(); ++j) sum += simpson_weight(j, points()) * at_[static_cast<std::size_t>(j)][0].value;
  return h * sum + at_.back().back().value;
}

void HermiteSimpson::objective_gradient(const double* z, double* gradient) {
  evaluate_points(z);
  const double h = (final_time(z) - t0_) / n_intervals_;
  std::fill(gradient, gradient + variables(), 0.0);
  double d_final_time = 0;
  for (int j = 0; j < points(); ++j) {
    const ValueGradient& L = at_[static_cast<std::size_t>(j)][0];
    const double w = simpson_weight(j, points());
    for (int i = 0; i < n_; ++i) {
      gradient[q_index(j, i)] += w * h * L.dq[static_cast<std::size_t>(i)];
      gradient[v_index(j, i)] += w * h * L.dv[static_cast<std::size_t>(i)];
    }
    // h = (T - t0)/N and t_j = t0 + (T - t0) j/(2N) both move with T.
    d_final_time += w * (L.value / n_intervals_ + h * L.dt * j / (2.0 * n_intervals_));
  }
  const ValueGradient& phi = at_.back().back();
  const int last = points() - 1;
  for (int i = 0; i < n_; ++i) {
    gradient[q_index(last, i)] += phi.dq[static_cast<std::size_t>(i)];
    gradient[v_index(last, i)] += phi.dv[static_cast<std::size_t>(i)];
  }
  if (free_time_) gradient[variables() - 1] = d_final_time + phi.dt;
}

// Rows: per interval k the n Hermite midpoint conditions, then the n Simpson conditions
//   q_m - (q_a + q_b)/2 - h/8 (v_a - v_b) = 0,   q_b - q_a - h/6 (v_a + 4 v_m + v_b) = 0,
// (a = 2k, m = 2k + 1, b = 2k + 2); then the scene's constraints at every point.
void HermiteSimpson::constraint_values(const double* z, double* g) {
  evaluate_points(z);
  const double h = (final_time(z) - t0_) / n_intervals_;
  int row = 0;
  for (int k = 0; k < n_intervals_; ++k) {
    const int a = 2 * k, m = a + 1, b = a + 2;
    for (int i = 0; i < n_; ++i)
      g[row++] = z[q_index(m, i)] - 0.5 * (z[q_index(a, i)] + z[q_index(b, i)]) - h / 8 * (z[v_index(a, i)] - z[v_index(b, i)]);
    for (int i = 0; i < n_; ++i)
      g[row++] = z[q_index(b, i)] - z[q_index(a, i)] - h / 6 * (z[v_index(a, i)] + 4 * z[v_index(m, i)] + z[v_index(b, i)]);
  }
  for (int j = 0; j < points(); ++j)
    for (int alpha = 0; alpha < m_; ++alpha) g[row++] = at_[static_cast<std::size_t>(j)][static_cast<std::size_t>(1 + alpha)].value;
}

void HermiteSimpson::jacobian_structure(int* rows, int* columns) const {
  int e = 0, row = 0;
  const int t_column = variables() - 1;
  auto put = [&](int r, int c) {
    rows[e] = r;
    columns[e] = c;
    ++e;
  };
  for (int k = 0; k < n_intervals_; ++k) {
    const int a = 2 * k, m = a + 1, b = a + 2;
    for (int i = 0; i < n_; ++i, ++row) {
      put(row, q_index(m, i)), put(row, q_index(a, i)), put(row, q_index(b, i));
      put(row, v_index(a, i)), put(row, v_index(b, i));
      if (free_time_) put(row, t_column);
    }
    for (int i = 0; i < n_; ++i, ++row) {
      put(row, q_index(b, i)), put(row, q_index(a, i));
      put(row, v_index(a, i)), put(row, v_index(m, i)), put(row, v_index(b, i));
      if (free_time_) put(row, t_column);
    }
  }
  for (int j = 0; j < points(); ++j)
    for (int alpha = 0; alpha < m_; ++alpha, ++row) {
      for (int i = 0; i < n_; ++i) put(row, q_index(j, i));
      for (int i = 0; i < n_; ++i) put(row, v_index(j, i));
      if (free_time_) put(row, t_column);
    }
}

void HermiteSimpson::jacobian_values(const double* z, double* values) {
  evaluate_points(z);
  const double h = (final_time(z) - t0_) / n_intervals_, dh = 1.0 / n_intervals_;
  int e = 0;
  for (int k = 0; k < n_intervals_; ++k) {
    const int a = 2 * k, m = a + 1, b = a + 2;
    for (int i = 0; i < n_; ++i) {
      values[e++] = 1, values[e++] = -0.5, values[e++] = -0.5;
      values[e++] = -h / 8, values[e++] = h / 8;
      if (free_time_) values[e++] = -dh / 8 * (z[v_index(a, i)] - z[v_index(b, i)]);
    }
    for (int i = 0; i < n_; ++i) {
      values[e++] = 1, values[e++] = -1;
      values[e++] = -h / 6, values[e++] = -4 * h / 6, values[e++] = -h / 6;
      if (free_time_) values[e++] = -dh / 6 * (z[v_index(a, i)] + 4 * z[v_index(m, i)] + z[v_index(b, i)]);
    }
  }
  for (int j = 0; j < points(); ++j)
    for (int alpha = 0; alpha < m_; ++alpha) {
      const ValueGradient& c = at_[static_cast<std::size_t>(j)][static_cast<std::size_t>(1 + alpha)];
      for (int i = 0; i < n_; ++i) values[e++] = c.dq[static_cast<std::size_t>(i)];
      for (int i = 0; i < n_; ++i) values[e++] = c.dv[static_cast<std::size_t>(i)];
      if (free_time_) values[e++] = c.dt * j / (2.0 * n_intervals_);
    }
}

std::vector<double> HermiteSimpson::straight_line() const {
  std::vector<double> z(static_cast<std::size_t>(variables()), 0.0);
  const double t_end = free_time_ ? 0.5 * (t_end_low_ + t_end_high_) : t_end_low_;
  if (free_time_) z.back() = t_end;
  const int last = points() - 1;
  // A value fixed at one end only is held along the line; clamp into the bounds.
  auto end_value = [&](int index, int other) {
    const auto k = static_cast<std::size_t>(index), o = static_cast<std::size_t>(other);
    if (low_[k] == high_[k]) return low_[k];
    if (low_[o] == high_[o]) return low_[o];
    return std::isfinite(low_[k]) && low_[k] > 0 ? low_[k] : std::isfinite(high_[k]) && high_[k] < 0 ? high_[k] : 0.0;
  };
  for (int i = 0; i < n_; ++i) {
    const double q0 = end_value(q_index(0, i), q_index(last, i)), q1 = end_value(q_index(last, i), q_index(0, i));
    const double rate = (q1 - q0) / (t_end - t0_);
    // Bent by a small bump eps sin((i + 1) pi s), which keeps the ends: on the straight line
    // itself a constraint's gradient may vanish (the Heisenberg system's at x = y = 0), a saddle
    // of the constraint violation where IPOPT stays (docs/optimize.md, "Start").
    const double frequency = (i + 1) * kPi;
    for (int j = 0; j < points(); ++j) {
      const double s = j / static_cast<double>(last);
      z[static_cast<std::size_t>(q_index(j, i))] = q0 + s * (q1 - q0) + kBend * std::sin(frequency * s);
      z[static_cast<std::size_t>(v_index(j, i))] = rate + kBend * frequency / (t_end - t0_) * std::cos(frequency * s);
    }
  }
  for (std::size_t k = 0; k < z.size(); ++k) z[k] = std::clamp(z[k], low_[k], high_[k]);
  return z;
}

std::vector<double> HermiteSimpson::from_samples(const std::vector<std::vector<double>>& rows, int time_column,
                                                 const std::vector<int>& q_columns, const std::vector<int>& v_columns) const {
  std::vector<double> z = straight_line();
  const auto tc = static_cast<std::size_t>(time_column);
  if (free_time_) z.back() = std::clamp(rows.back()[tc], t_end_low_, t_end_high_);
  auto interpolate = [&](double t, int column) {
    const auto c = static_cast<std::size_t>(column);
    if (t <= rows.front()[tc]) return rows.front()[c];
    if (t >= rows.back()[tc]) return rows.back()[c];
    const auto it = std::upper_bound(rows.begin(), rows.end(), t, [&](double x, const std::vector<double>& r) { return x < r[tc]; });
    const std::vector<double>& r1 = *it;
    const std::vector<double>& r0 = *(it - 1);
    const double s = r1[tc] > r0[tc] ? (t - r0[tc]) / (r1[tc] - r0[tc]) : 0.0;
    return r0[c] + s * (r1[c] - r0[c]);
  };
  const double dt = (final_time(z.data()) - t0_) / (2.0 * n_intervals_);
  for (int j = 0; j < points(); ++j) {
    const double t = time(j, z.data());
    for (int i = 0; i < n_; ++i) {
      const int qc = q_columns[static_cast<std::size_t>(i)], vc = v_columns[static_cast<std::size_t>(i)];
      if (qc >= 0) z[static_cast<std::size_t>(q_index(j, i))] = interpolate(t, qc);
      if (vc >= 0) z[static_cast<std::size_t>(v_index(j, i))] = interpolate(t, vc);
    }
  }
  for (int i = 0; i < n_; ++i)
    if (v_columns[static_cast<std::size_t>(i)] < 0 && q_columns[static_cast<std::size_t>(i)] >= 0)
      for (int j = 0; j < points(); ++j) {
        const int lo = std::max(j - 1, 0), hi = std::min(j + 1, points() - 1);
        z[static_cast<std::size_t>(v_index(j, i))] =
            (z[static_cast<std::size_t>(q_index(hi, i))] - z[static_cast<std::size_t>(q_index(lo, i))]) / ((hi - lo) * dt);
      }
  for (std::size_t k = 0; k < z.size(); ++k) z[k] = std::clamp(z[k], low_[k], high_[k]);
  return z;
}

std::string HermiteSimpson::constraint_name(int row, const double* z) const {
  const int collocation_rows = n_intervals_ * 2 * n_;
  if (row < collocation_rows) {
    const int k = row / (2 * n_), i = row % n_;
    return fmt::format("the collocation of {} (its path's slope equal to {}') on [{:.6g}, {:.6g}]",
                       coordinate_names_[static_cast<std::size_t>(i)], coordinate_names_[static_cast<std::size_t>(i)],
                       time(2 * k, z), time(2 * k + 2, z));
  }
  const int j = (row - collocation_rows) / m_, alpha = (row - collocation_rows) % m_;
  return fmt::format("the constraint {} = 0 at t = {:.6g}", functions_.constraint_text(alpha), time(j, z));
}

}  // namespace nhc::optimize
