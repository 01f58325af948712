#include "nhc/linearize/sweep.hpp"

#include "nhc/base/number_text.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <cstdlib>
#include <sstream>

#include "nhc/errors.hpp"

namespace nhc {

namespace {

[[noreturn]] void bad_sweep(const std::string& flag, const std::string& message) {
  throw InputError({flag, 0, 0}, message);
}

double parse_number(const std::string& text, const std::string& flag, const std::string& whole) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v))
    bad_sweep(flag, flag + " " + whole + ": '" + text + "' is not a finite number");
  return v;
}

std::string full_digits(double v) { return base::number_text(v, 17); }

}  // namespace

SweepRange parse_sweep_range(const std::string& text, const std::string& flag) {
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    bad_sweep(flag, flag + " " + text + ": expected NAME=a:b:n (e.g. ps'=1:10:19)");
  const std::string spec = text.substr(eq + 1);
  const std::size_t c1 = spec.find(':');
  const std::size_t c2 = c1 == std::string::npos ? c1 : spec.find(':', c1 + 1);
  if (c2 == std::string::npos || spec.find(':', c2 + 1) != std::string::npos)
    bad_sweep(flag, flag + " " + text + ": expected NAME=a:b:n (three fields after '=')");
  SweepRange r;
  r.name = text.substr(0, eq);
  r.first = parse_number(spec.substr(0, c1), flag, text);
  r.last = parse_number(spec.substr(c1 + 1, c2 - c1 - 1), flag, text);
  const std::string count = spec.substr(c2 + 1);
  char* end = nullptr;
  const long n = std::strtol(count.c_str(), &end, 10);
  if (count.empty() || end != count.c_str() + count.size())
    bad_sweep(flag, flag + " " + text + ": n = '" + count + "' is not an integer");
  if (n < 2) bad_sweep(flag, flag + " " + text + ": n must be at least 2 (a and b are both included)");
  if (n > 100000) bad_sweep(flag, flag + " " + text + ": n must be at most 100000");
  if (!(r.first < r.last)) bad_sweep(flag, flag + " " + text + ": a must be less than b");
  r.count = static_cast<int>(n);
  return r;
}

/// Which side of a threshold a point lies on, as a number whose sign changes there. Between an
/// unstable and a stable end this is continuous: the largest real part among the eigenvalues
/// that are not the steady-motion families' zeros (the `families` of the stable end, taken as
/// the eigenvalues nearest 0); the root is where an eigenvalue crosses the axis, free of the zero
/// tolerance that the verdict applies (a real eigenvalue crossing 0 passes through the zero band,
/// which bisection on the verdict would report as the threshold). Against an asymptotically
/// stable end the root is Re = 0 itself; against a marginally stable end, whose real parts are 0
/// up to rounding, it is Re = the axis tolerance, so that rounding cannot pass for instability.
/// Otherwise it is ±1 by the verdict: "same as the lower end or not".
class ThresholdSide {
 public:
  ThresholdSide(const Linearization& lower, const Linearization& upper, double tolerance) : lower_(lower.verdict) {
    const bool lower_unstable = lower.verdict == StabilityVerdict::unstable;
    continuous_ = lower_unstable != (upper.verdict == StabilityVerdict::unstable);
    const Linearization& stable = lower_unstable ? upper : lower;
    families_ = stable.families.size();
    tolerance_ = stable.verdict == StabilityVerdict::asymptotically_stable ? 0.0 : tolerance;
  }
  bool continuous() const { return continuous_; }
  double operator()(const Linearization& l) const {
    if (!continuous_) return l.verdict == lower_ ? -1.0 : 1.0;
    std::vector<std::complex<double>> rest(l.eigenvalues.begin(), l.eigenvalues.end());
    std::sort(rest.begin(), rest.end(), [](auto x, auto y) { return std::abs(x) < std::abs(y); });
    double largest = -std::numeric_limits<double>::infinity();
    for (std::size_t k = std::min(families_, rest.size()); k < rest.size(); ++k)
      largest = std::max(largest, rest[k].real());
    const double scale = std::max(1.0, l.A.size() ? l.A.cwiseAbs().rowwise().sum().maxCoeff() : 0.0);
    return largest - tolerance_ * scale;
  }

 private:
  StabilityVerdict lower_;
  double tolerance_ = 0.0;
  bool continuous_ = false;
  std::size_t families_ = 0;
};

SweepResult sweep(const Linearizer& linearizer, const std::vector<PointOverride>& overrides, const SweepRange& range,
                  double relative_width) {
  resolve_override(linearizer.scene(), range.name, "--sweep");
  SweepResult out;
  out.range = range;
  auto at = [&](double value) {
    std::vector<PointOverride> all = overrides;
    all.push_back({range.name, value});
    try {
      return linearizer.at(all);
    } catch (const MathError& e) {
      throw MathError("at " + range.name + " = " + full_digits(value) + ": " + e.what());
    }
  };
  for (int k = 0; k < range.count; ++k) {
    const double value =
        k + 1 == range.count ? range.last : range.first + (range.last - range.first) * k / (range.count - 1);
    out.points.push_back({value, at(value)});
  }
  for (std::size_t k = 0; k + 1 < out.points.size(); ++k) {
    const Linearization& a = out.points[k].linearization;
    const Linearization& b = out.points[k + 1].linearization;
    if (a.verdict == b.verdict) continue;
    const ThresholdSide side(a, b, linearizer.options().tolerance);
    double lo = out.points[k].value, hi = out.points[k + 1].value;
    double g_lo = side(a), g_hi = side(b);
    auto update = [&](double x, double g) {
      if ((g > 0) == (g_lo > 0)) lo = x, g_lo = g;
      else hi = x, g_hi = g;
    };
    const auto width = [&] { return relative_width * std::max(std::abs(lo), std::abs(hi)); };
    for (int step = 0; hi - lo > width() && hi - lo > 1e-300 && step < 400; ++step) {
      // Regula falsi on a continuous side function (every other step, and whenever it falls
      // outside the bracket, bisection), then a probe just past the estimate that closes the
      // bracket once the estimate is within the target width.
      double x = lo + (hi - lo) / 2;
      const bool continuous = side.continuous();
      if (continuous && step % 2 == 0) {
        const double falsi = lo - g_lo * (hi - lo) / (g_hi - g_lo);
        if (falsi > lo && falsi < hi) x = falsi;
      }
      if (x <= lo || x >= hi) break;
      update(x, side(at(x)));
      if (!continuous || hi - lo <= width()) continue;
      const double probe = x == lo ? x + 0.5 * width() : x - 0.5 * width();
      if (probe > lo && probe < hi) update(probe, side(at(probe)));
    }
    out.thresholds.push_back({lo + (hi - lo) / 2, lo, hi, a.verdict, b.verdict});
  }
  return out;
}

}  // namespace nhc
