#include "nhc/optimize/hermite_simpson.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace nhc::optimize {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;
/// The amplitude of the straight line's bend (straight_line()).
constexpr double kBend = 1e-2;
/// A hidden constraint that the fixed initial values meet to this is dropped, not imposed.
constexpr double kInitialTolerance = 1e-9;
constexpr int kIntegrand = 0, kFinalCost = 1, kFirstPathRow = 2;

/// N equal intervals: the node fractions k/N.
std::vector<double> equal_mesh(int intervals) {
  std::vector<double> mesh(static_cast<std::size_t>(intervals) + 1);
  for (int k = 0; k <= intervals; ++k) mesh[static_cast<std::size_t>(k)] = static_cast<double>(k) / intervals;
  mesh.back() = 1.0;
  return mesh;
}

}  // namespace

HermiteSimpson::HermiteSimpson(const Scene& scene, const Settings& settings, int intervals)
    : HermiteSimpson(scene, settings, optimize::point_problem(scene, settings), intervals) {}

HermiteSimpson::HermiteSimpson(const Scene& scene, const Settings& settings, PointProblem problem, int intervals)
    : HermiteSimpson(scene, settings, std::move(problem), equal_mesh(intervals)) {}

HermiteSimpson::HermiteSimpson(const Scene& scene, const Settings& settings, PointProblem problem,
                               std::vector<double> mesh)
    : problem_(std::move(problem)),
      n_(problem_.states),
      stride_(problem_.slots()),
      n_intervals_(static_cast<int>(mesh.size()) - 1),
      t0_(scene.initial.t0),
      t_end_low_(settings.t_end_low),
      t_end_high_(settings.t_end_high),
      free_time_(settings.free_time()),
      functions_(std::make_shared<PathFunctions>(problem_)),
      initial_where_(problem_.initial.empty() ? settings.table_where : problem_.initial.front().where) {
  set_up(mesh);
}

HermiteSimpson::HermiteSimpson(const HermiteSimpson& other, std::vector<double> mesh, Shared)
    : problem_(other.problem_),
      n_(other.n_),
      stride_(other.stride_),
      n_intervals_(static_cast<int>(mesh.size()) - 1),
      t0_(other.t0_),
      t_end_low_(other.t_end_low_),
      t_end_high_(other.t_end_high_),
      free_time_(other.free_time_),
      functions_(other.functions_),
      initial_where_(other.initial_where_) {
  set_up(mesh);
}

HermiteSimpson HermiteSimpson::remeshed(std::vector<double> mesh) const {
  return HermiteSimpson(*this, std::move(mesh), Shared{});
}

void HermiteSimpson::set_up(const std::vector<double>& mesh) {
  // Point fractions and Simpson's weights h_k/6 at each end of interval k (a node inside the
  // mesh ends two), 4 h_k/6 at its midpoint, in units of T - t0.
  s_.assign(static_cast<std::size_t>(points()), 0.0);
  weight_.assign(static_cast<std::size_t>(points()), 0.0);
  for (int k = 0; k < n_intervals_; ++k) {
    const double a = mesh[static_cast<std::size_t>(k)], b = mesh[static_cast<std::size_t>(k) + 1], d = b - a;
    s_[static_cast<std::size_t>(2 * k)] = a;
    s_[static_cast<std::size_t>(2 * k + 1)] = 0.5 * (a + b);
    s_[static_cast<std::size_t>(2 * k + 2)] = b;
    weight_[static_cast<std::size_t>(2 * k)] += d / 6;
    weight_[static_cast<std::size_t>(2 * k + 1)] += 4 * d / 6;
    weight_[static_cast<std::size_t>(2 * k + 2)] += d / 6;
  }
  for (int i = 0; i < n_; ++i)
    if (problem_.collocated[static_cast<std::size_t>(i)]) collocated_.push_back(i);
  low_.assign(static_cast<std::size_t>(variables()), -kInfinity);
  high_.assign(static_cast<std::size_t>(variables()), kInfinity);
  // An algebraic state's rate is no variable of the problem: held at 0.
  for (int i = 0; i < n_; ++i)
    if (!problem_.collocated[static_cast<std::size_t>(i)])
      for (int j = 0; j < points(); ++j)
        low_[static_cast<std::size_t>(v_index(j, i))] = high_[static_cast<std::size_t>(v_index(j, i))] = 0;
  for (const SlotBound& b : problem_.bounds)
    for (int j = 0; j < points(); ++j) {
      const auto k = static_cast<std::size_t>(j * stride_ + b.slot);
      low_[k] = std::max(low_[k], b.low);
      high_[k] = std::min(high_[k], b.high);
    }
  auto fix = [&](const std::vector<SlotBound>& values, int point, const char* table) {
    for (const SlotBound& b : values) {
      const auto k = static_cast<std::size_t>(point * stride_ + b.slot);
      if (b.high < low_[k] || b.low > high_[k])
        throw InputError(
            b.where, fmt::format("{} = {} in [optimize.{}] is outside its bound [{}, {}] in [optimize.bounds]", b.name,
                                 b.low == b.high ? fmt::format("{}", b.low) : fmt::format("[{}, {}]", b.low, b.high),
                                 table, low_[k], high_[k]));
      low_[k] = std::max(low_[k], b.low);
      high_[k] = std::min(high_[k], b.high);
    }
  };
  if (problem_.measured_start) {
    for (const SlotBound& b : problem_.initial)
      low_[static_cast<std::size_t>(b.slot)] = high_[static_cast<std::size_t>(b.slot)] = b.low;
  } else {
    fix(problem_.initial, 0, "initial");
  }
  fix(problem_.final, points() - 1, "final");
  if (free_time_) {
    low_.back() = t_end_low_;
    high_.back() = t_end_high_;
  }
  drop_fixed_initial_rows();
  build_hessian_structure();
}

// The Lagrangian's second derivatives: each function's pairs at every point where it is
// evaluated (the integrand, the path rows: all points; the final cost: the last; the initial
// rows: the first) and, with a free T, the whole row of T (T moves h and every t_j; the
// collocation rows are bilinear in T and the rates).
void HermiteSimpson::build_hessian_structure() {
  auto add = [&](int r, int c) {
    if (r < c) std::swap(r, c);
    if (hessian_index_.emplace(std::make_pair(r, c), static_cast<int>(hessian_entries_.size())).second)
      hessian_entries_.emplace_back(r, c);
  };
  auto add_pairs = [&](int f, int point) {
    for (const VariablePair& p : functions_->pairs(f))
      if (p.first >= 0 && p.second >= 0) add(point * stride_ + p.first, point * stride_ + p.second);
  };
  const int first_initial = kFirstPathRow + path_rows();
  for (int j = 0; j < points(); ++j) {
    add_pairs(kIntegrand, j);
    for (int r = 0; r < path_rows(); ++r) add_pairs(kFirstPathRow + r, j);
  }
  add_pairs(kFinalCost, points() - 1);
  for (int r : kept_initial_rows_) add_pairs(first_initial + r, 0);
  if (free_time_)
    for (int k = 0; k < variables(); ++k) add(variables() - 1, k);
}

int HermiteSimpson::hessian_entry(int row, int column) const {
  if (row < column) std::swap(row, column);
  return hessian_index_.at({row, column});
}

void HermiteSimpson::hessian_structure(int* rows, int* columns) const {
  for (std::size_t e = 0; e < hessian_entries_.size(); ++e) {
    rows[e] = hessian_entries_[e].first;
    columns[e] = hessian_entries_[e].second;
  }
}

void HermiteSimpson::hessian_values(const double* z, double sigma, const double* lambda, double* values) {
  std::fill(values, values + hessian_nonzeros(), 0.0);
  const double D = final_time(z) - t0_;
  const int T = variables() - 1;
  // d(t_j)/dT = s_j = j/(2N); for the function f with factor c at point j: c f_ab at (a, b) and,
  // with a free T, c f_ta s_j at (T, a) and c f_tt s_j^2 at (T, T).
  auto add_function = [&](int f, int j, double c, double s_j) {
    const ValueGradient& v = functions_->value(f);
    const std::vector<VariablePair>& pairs = functions_->pairs(f);
    for (std::size_t e = 0; e < pairs.size(); ++e) {
      const auto [a, b] = pairs[e];
      if (a >= 0 && b >= 0) values[hessian_entry(j * stride_ + a, j * stride_ + b)] += c * v.dd[e];
      else if (free_time_ && a >= 0) values[hessian_entry(T, j * stride_ + a)] += c * v.dd[e] * s_j;
      else if (free_time_) values[hessian_entry(T, T)] += c * v.dd[e] * s_j * s_j;
    }
  };
  const int first_initial = kFirstPathRow + path_rows();
  int row = collocation_rows();
  for (int j = 0; j < points(); ++j) {
    const double t = time(j, z), s_j = s_[static_cast<std::size_t>(j)], w = weight_[static_cast<std::size_t>(j)];
    functions_->evaluate(t, z + q_index(j, 0));
    functions_->evaluate_second(t, z + q_index(j, 0));
    add_function(kIntegrand, j, sigma * w * D, s_j);
    if (free_time_) {
      // f = (T - t0) sum_j w_j l(t_j, p_j): d2f/dT dp_a = w_j (l_a + (T - t0) l_ta s_j) (the
      // second term above); d2f/dT2 = sum_j w_j (2 l_t s_j + (T - t0) l_tt s_j^2).
      const ValueGradient& l = functions_->value(kIntegrand);
      const std::vector<int>& slots = functions_->slots(kIntegrand);
      for (std::size_t e = 0; e < slots.size(); ++e)
        values[hessian_entry(T, j * stride_ + slots[e])] += sigma * w * l.d[e];
      values[hessian_entry(T, T)] += sigma * w * 2 * l.dt * s_j;
    }
    for (int r = 0; r < path_rows(); ++r) add_function(kFirstPathRow + r, j, lambda[row + j * path_rows() + r], s_j);
    if (j == 0) {
      int initial_row = row + points() * path_rows();
      for (int r : kept_initial_rows_) add_function(first_initial + r, 0, lambda[initial_row++], 0.0);
    }
    if (j == points() - 1) add_function(kFinalCost, j, sigma, 1.0);
  }
  if (free_time_) {
    int r = 0;
    for (int k = 0; k < n_intervals_; ++k) {
      const int a = 2 * k, m = a + 1, b = a + 2;
      const double dh = s_[static_cast<std::size_t>(b)] - s_[static_cast<std::size_t>(a)];
      for (int i : collocated_) {
        values[hessian_entry(T, v_index(a, i))] += -dh / 8 * lambda[r];
        values[hessian_entry(T, v_index(b, i))] += dh / 8 * lambda[r];
        ++r;
      }
      for (int i : collocated_) {
        values[hessian_entry(T, v_index(a, i))] += -dh / 6 * lambda[r];
        values[hessian_entry(T, v_index(m, i))] += -4 * dh / 6 * lambda[r];
        values[hessian_entry(T, v_index(b, i))] += -dh / 6 * lambda[r];
        ++r;
      }
    }
  }
}

void HermiteSimpson::drop_fixed_initial_rows() {
  std::vector<double> point(static_cast<std::size_t>(stride_), 0.0);
  for (int s = 0; s < stride_; ++s)
    if (low_[static_cast<std::size_t>(s)] == high_[static_cast<std::size_t>(s)])
      point[static_cast<std::size_t>(s)] = low_[static_cast<std::size_t>(s)];
  functions_->evaluate(t0_, point.data());
  const int first = kFirstPathRow + path_rows();
  for (int r = 0; r < static_cast<int>(problem_.initial_rows.size()); ++r) {
    const std::vector<int>& slots = functions_->slots(first + r);
    const bool fixed = std::all_of(slots.begin(), slots.end(), [&](int s) {
      return low_[static_cast<std::size_t>(s)] == high_[static_cast<std::size_t>(s)];
    });
    if (!fixed) {
      kept_initial_rows_.push_back(r);
      continue;
    }
    if (problem_.measured_start) continue;
    const double value = functions_->value(first + r).value;
    if (!(std::abs(value) <= kInitialTolerance))
      throw InputError(initial_where_, fmt::format("the values of [optimize.initial] violate {}: it is {:.6g} there",
                                                   problem_.initial_rows[static_cast<std::size_t>(r)].name, value));
  }
}

int HermiteSimpson::jacobian_nonzeros() const noexcept {
  const int t = free_time_ ? 1 : 0;
  int count = collocation_rows() * (5 + t);
  for (int r = 0; r < path_rows(); ++r)
    count += points() * (static_cast<int>(functions_->slots(kFirstPathRow + r).size()) + t);
  for (int r : kept_initial_rows_) count += static_cast<int>(functions_->slots(kFirstPathRow + path_rows() + r).size());
  return count;
}

double HermiteSimpson::time(int point, const double* z) const noexcept {
  return t0_ + (final_time(z) - t0_) * s_[static_cast<std::size_t>(point)];
}

void HermiteSimpson::variable_bounds(double* low, double* high) const {
  std::copy(low_.begin(), low_.end(), low);
  std::copy(high_.begin(), high_.end(), high);
}

void HermiteSimpson::constraint_bounds(double* low, double* high) const {
  std::fill(low, low + constraints(), 0.0);
  std::fill(high, high + constraints(), 0.0);
  int row = collocation_rows();
  for (int j = 0; j < points(); ++j)
    for (const PointRow& r : problem_.path) {
      low[row] = r.low;
      high[row] = r.high;
      ++row;
    }
  for (int r : kept_initial_rows_) {
    low[row] = problem_.initial_rows[static_cast<std::size_t>(r)].low;
    high[row] = problem_.initial_rows[static_cast<std::size_t>(r)].high;
    ++row;
  }
}

void HermiteSimpson::evaluate_points(const double* z, bool derivatives) {
  const auto size = static_cast<std::size_t>(variables());
  if (cached_.size() == size && (cached_derivatives_ || !derivatives) &&
      std::memcmp(cached_.data(), z, size * sizeof(double)) == 0)
    return;
  cached_.assign(z, z + size);
  cached_derivatives_ = derivatives;
  at_.resize(static_cast<std::size_t>(points()));
  for (int j = 0; j < points(); ++j) {
    if (derivatives) functions_->evaluate(time(j, z), z + q_index(j, 0));
    else functions_->evaluate_values(time(j, z), z + q_index(j, 0));
    std::vector<ValueGradient>& here = at_[static_cast<std::size_t>(j)];
    here.clear();
    for (int f = 0; f < functions_->functions(); ++f) here.push_back(functions_->value(f));
  }
}

double HermiteSimpson::objective(const double* z) {
  evaluate_points(z, false);
  double sum = 0;
  for (int j = 0; j < points(); ++j)
    sum += weight_[static_cast<std::size_t>(j)] * at_[static_cast<std::size_t>(j)][kIntegrand].value;
  return (final_time(z) - t0_) * sum + at_.back()[kFinalCost].value;
}

void HermiteSimpson::objective_gradient(const double* z, double* gradient) {
  evaluate_points(z, true);
  const double D = final_time(z) - t0_;
  std::fill(gradient, gradient + variables(), 0.0);
  double d_final_time = 0;
  const std::vector<int>& slots = functions_->slots(kIntegrand);
  for (int j = 0; j < points(); ++j) {
    const ValueGradient& L = at_[static_cast<std::size_t>(j)][kIntegrand];
    const double w = weight_[static_cast<std::size_t>(j)];
    for (std::size_t e = 0; e < slots.size(); ++e) gradient[j * stride_ + slots[e]] += w * D * L.d[e];
    // The weights (T - t0) w_j and t_j = t0 + (T - t0) s_j both move with T.
    d_final_time += w * (L.value + D * L.dt * s_[static_cast<std::size_t>(j)]);
  }
  const ValueGradient& phi = at_.back()[kFinalCost];
  const int last = points() - 1;
  const std::vector<int>& phi_slots = functions_->slots(kFinalCost);
  for (std::size_t e = 0; e < phi_slots.size(); ++e) gradient[last * stride_ + phi_slots[e]] += phi.d[e];
  if (free_time_) gradient[variables() - 1] = d_final_time + phi.dt;
}

// Rows: per interval k, per collocated state i, the Hermite midpoint condition and Simpson's rule
//   y_m - (y_a + y_b)/2 - h/8 (y'_a - y'_b) = 0,   y_b - y_a - h/6 (y'_a + 4 y'_m + y'_b) = 0,
// (a = 2k, m = 2k + 1, b = 2k + 2); then the path rows at every point; then the kept initial rows.
void HermiteSimpson::constraint_values(const double* z, double* g) {
  evaluate_points(z, false);
  int row = 0;
  for (int k = 0; k < n_intervals_; ++k) {
    const int a = 2 * k, m = a + 1, b = a + 2;
    const double h = interval_length(k, z);
    for (int i : collocated_)
      g[row++] = z[q_index(m, i)] - 0.5 * (z[q_index(a, i)] + z[q_index(b, i)]) -
                 h / 8 * (z[v_index(a, i)] - z[v_index(b, i)]);
    for (int i : collocated_)
      g[row++] =
          z[q_index(b, i)] - z[q_index(a, i)] - h / 6 * (z[v_index(a, i)] + 4 * z[v_index(m, i)] + z[v_index(b, i)]);
  }
  for (int j = 0; j < points(); ++j)
    for (int r = 0; r < path_rows(); ++r)
      g[row++] = at_[static_cast<std::size_t>(j)][static_cast<std::size_t>(kFirstPathRow + r)].value;
  for (int r : kept_initial_rows_)
    g[row++] = at_.front()[static_cast<std::size_t>(kFirstPathRow + path_rows() + r)].value;
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
    for (int i : collocated_) {
      put(row, q_index(m, i)), put(row, q_index(a, i)), put(row, q_index(b, i));
      put(row, v_index(a, i)), put(row, v_index(b, i));
      if (free_time_) put(row, t_column);
      ++row;
    }
    for (int i : collocated_) {
      put(row, q_index(b, i)), put(row, q_index(a, i));
      put(row, v_index(a, i)), put(row, v_index(m, i)), put(row, v_index(b, i));
      if (free_time_) put(row, t_column);
      ++row;
    }
  }
  for (int j = 0; j < points(); ++j)
    for (int r = 0; r < path_rows(); ++r, ++row) {
      for (int s : functions_->slots(kFirstPathRow + r)) put(row, j * stride_ + s);
      if (free_time_) put(row, t_column);
    }
  for (int r : kept_initial_rows_) {
    for (int s : functions_->slots(kFirstPathRow + path_rows() + r)) put(row, s);
    ++row;
  }
}

void HermiteSimpson::jacobian_values(const double* z, double* values) {
  evaluate_points(z, true);
  int e = 0;
  for (int k = 0; k < n_intervals_; ++k) {
    const int a = 2 * k, m = a + 1, b = a + 2;
    const double h = interval_length(k, z), dh = s_[static_cast<std::size_t>(b)] - s_[static_cast<std::size_t>(a)];
    for (int i : collocated_) {
      values[e++] = 1, values[e++] = -0.5, values[e++] = -0.5;
      values[e++] = -h / 8, values[e++] = h / 8;
      if (free_time_) values[e++] = -dh / 8 * (z[v_index(a, i)] - z[v_index(b, i)]);
    }
    for (int i : collocated_) {
      values[e++] = 1, values[e++] = -1;
      values[e++] = -h / 6, values[e++] = -4 * h / 6, values[e++] = -h / 6;
      if (free_time_) values[e++] = -dh / 6 * (z[v_index(a, i)] + 4 * z[v_index(m, i)] + z[v_index(b, i)]);
    }
  }
  for (int j = 0; j < points(); ++j)
    for (int r = 0; r < path_rows(); ++r) {
      const ValueGradient& c = at_[static_cast<std::size_t>(j)][static_cast<std::size_t>(kFirstPathRow + r)];
      for (double d : c.d) values[e++] = d;
      if (free_time_) values[e++] = c.dt * s_[static_cast<std::size_t>(j)];
    }
  for (int r : kept_initial_rows_)
    for (double d : at_.front()[static_cast<std::size_t>(kFirstPathRow + path_rows() + r)].d) values[e++] = d;
}

std::vector<double> HermiteSimpson::straight_line() const {
  std::vector<double> z(static_cast<std::size_t>(variables()), 0.0);
  const double t_end = free_time_ ? 0.5 * (t_end_low_ + t_end_high_) : t_end_low_;
  if (free_time_) z.back() = t_end;
  const int last = points() - 1;
  // A value fixed at one end only is held along the line; clamp into the bounds.
  auto end_value = [&](int index, int other) {
    const auto k = static_cast<std::size_t>(index), o = static_cast<std::size_t>(other);
    auto middle = [&](std::size_t c) {
      return std::isfinite(low_[c]) && std::isfinite(high_[c]) ? 0.5 * (low_[c] + high_[c]) : low_[c];
    };
    if (low_[k] == high_[k]) return low_[k];
    if (low_[o] == high_[o]) return low_[o];
    if (std::isfinite(low_[k]) && std::isfinite(high_[k])) return middle(k);
    if (std::isfinite(low_[o]) && std::isfinite(high_[o])) return middle(o);
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
      const double s = s_[static_cast<std::size_t>(j)];
      z[static_cast<std::size_t>(q_index(j, i))] = q0 + s * (q1 - q0) + kBend * std::sin(frequency * s);
      z[static_cast<std::size_t>(v_index(j, i))] = rate + kBend * frequency / (t_end - t0_) * std::cos(frequency * s);
    }
  }
  for (std::size_t k = 0; k < z.size(); ++k) z[k] = std::clamp(z[k], low_[k], high_[k]);
  return z;
}

std::vector<double> HermiteSimpson::from_samples(const std::vector<std::vector<double>>& rows, int time_column,
                                                 const std::vector<int>& q_columns, const std::vector<int>& v_columns,
                                                 const std::vector<int>& u_columns) const {
  std::vector<double> z = straight_line();
  const auto tc = static_cast<std::size_t>(time_column);
  if (free_time_) z.back() = std::clamp(rows.back()[tc], t_end_low_, t_end_high_);
  auto interpolate = [&](double t, int column) {
    const auto c = static_cast<std::size_t>(column);
    if (t <= rows.front()[tc]) return rows.front()[c];
    if (t >= rows.back()[tc]) return rows.back()[c];
    const auto it = std::upper_bound(rows.begin(), rows.end(), t,
                                     [&](double x, const std::vector<double>& r) { return x < r[tc]; });
    const std::vector<double>& r1 = *it;
    const std::vector<double>& r0 = *(it - 1);
    const double s = r1[tc] > r0[tc] ? (t - r0[tc]) / (r1[tc] - r0[tc]) : 0.0;
    return r0[c] + s * (r1[c] - r0[c]);
  };
  for (int j = 0; j < points(); ++j) {
    const double t = time(j, z.data());
    for (int i = 0; i < n_; ++i) {
      const int qc = q_columns[static_cast<std::size_t>(i)], vc = v_columns[static_cast<std::size_t>(i)];
      if (qc >= 0) z[static_cast<std::size_t>(q_index(j, i))] = interpolate(t, qc);
      if (vc >= 0) z[static_cast<std::size_t>(v_index(j, i))] = interpolate(t, vc);
    }
    for (std::size_t k = 0; k < u_columns.size(); ++k)
      if (u_columns[k] >= 0)
        z[static_cast<std::size_t>(u_index(j, static_cast<int>(k)))] = interpolate(t, u_columns[k]);
  }
  for (int i = 0; i < n_; ++i)
    if (v_columns[static_cast<std::size_t>(i)] < 0 && q_columns[static_cast<std::size_t>(i)] >= 0)
      for (int j = 0; j < points(); ++j) {
        const int lo = std::max(j - 1, 0), hi = std::min(j + 1, points() - 1);
        z[static_cast<std::size_t>(v_index(j, i))] =
            (z[static_cast<std::size_t>(q_index(hi, i))] - z[static_cast<std::size_t>(q_index(lo, i))]) /
            (time(hi, z.data()) - time(lo, z.data()));
      }
  for (std::size_t k = 0; k < z.size(); ++k) z[k] = std::clamp(z[k], low_[k], high_[k]);
  return z;
}

void HermiteSimpson::restart(double t0, const std::vector<double>& start) {
  if (free_time_ || start.size() != problem_.initial.size())
    throw std::logic_error("HermiteSimpson::restart: a fixed final time and one value per initial slot");
  const double length = t_end_low_ - t0_;
  t0_ = t0;
  t_end_low_ = t_end_high_ = t0 + length;
  for (std::size_t i = 0; i < start.size(); ++i) {
    const auto k = static_cast<std::size_t>(problem_.initial[i].slot);
    low_[k] = high_[k] = start[i];
  }
  cached_.clear();  // the points' times moved: the functions' values at z are no longer those cached
}

std::vector<double> HermiteSimpson::mesh() const {
  std::vector<double> out;
  for (int j = 0; j < points(); j += 2) out.push_back(s_[static_cast<std::size_t>(j)]);
  return out;
}

std::string HermiteSimpson::constraint_name(int row, const double* z) const {
  if (row < collocation_rows()) {
    const int per_interval = 2 * static_cast<int>(collocated_.size());
    const int k = row / per_interval;
    const int i = collocated_[static_cast<std::size_t>(row % static_cast<int>(collocated_.size()))];
    const std::string& name = problem_.state_names[static_cast<std::size_t>(i)];
    return fmt::format("the collocation of {} (its path's slope equal to its rate {}') on [{:.6g}, {:.6g}]", name, name,
                       time(2 * k, z), time(2 * k + 2, z));
  }
  row -= collocation_rows();
  if (row < points() * path_rows()) {
    const int j = row / path_rows(), r = row % path_rows();
    return fmt::format("{} at t = {:.6g}", problem_.path[static_cast<std::size_t>(r)].name, time(j, z));
  }
  row -= points() * path_rows();
  const int r = kept_initial_rows_[static_cast<std::size_t>(row)];
  return fmt::format("{} at t = {:.6g}", problem_.initial_rows[static_cast<std::size_t>(r)].name, t0_);
}

}  // namespace nhc::optimize
