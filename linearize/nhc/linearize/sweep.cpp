#include "nhc/linearize/sweep.hpp"

#include <cmath>
#include <cstdlib>
#include <sstream>

#include "nhc/errors.hpp"

namespace nhc {

namespace {

[[noreturn]] void bad(const std::string& flag, const std::string& message) {
  throw InputError({flag, 0, 0}, message);
}

double parse_number(const std::string& text, const std::string& flag, const std::string& whole) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v))
    bad(flag, flag + " " + whole + ": '" + text + "' is not a finite number");
  return v;
}

std::string number(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

}  // namespace

SweepRange parse_sweep_range(const std::string& text, const std::string& flag) {
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0) bad(flag, flag + " " + text + ": expected NAME=a:b:n (e.g. ps'=1:10:19)");
  const std::string spec = text.substr(eq + 1);
  const std::size_t c1 = spec.find(':');
  const std::size_t c2 = c1 == std::string::npos ? c1 : spec.find(':', c1 + 1);
  if (c2 == std::string::npos || spec.find(':', c2 + 1) != std::string::npos)
    bad(flag, flag + " " + text + ": expected NAME=a:b:n (three fields after '=')");
  SweepRange r;
  r.name = text.substr(0, eq);
  r.first = parse_number(spec.substr(0, c1), flag, text);
  r.last = parse_number(spec.substr(c1 + 1, c2 - c1 - 1), flag, text);
  const std::string count = spec.substr(c2 + 1);
  char* end = nullptr;
  const long n = std::strtol(count.c_str(), &end, 10);
  if (count.empty() || end != count.c_str() + count.size())
    bad(flag, flag + " " + text + ": n = '" + count + "' is not an integer");
  if (n < 2) bad(flag, flag + " " + text + ": n must be at least 2 (a and b are both included)");
  if (n > 100000) bad(flag, flag + " " + text + ": n must be at most 100000");
  if (!(r.first < r.last)) bad(flag, flag + " " + text + ": a must be less than b");
  r.count = static_cast<int>(n);
  return r;
}

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
      throw MathError("at " + range.name + " = " + number(value) + ": " + e.what());
    }
  };
  for (int k = 0; k < range.count; ++k) {
    const double value = k + 1 == range.count
                             ? range.last
                             : range.first + (range.last - range.first) * k / (range.count - 1);
    out.points.push_back({value, at(value)});
  }
  for (std::size_t k = 0; k + 1 < out.points.size(); ++k) {
    const StabilityVerdict from = out.points[k].linearization.verdict;
    const StabilityVerdict to = out.points[k + 1].linearization.verdict;
    if (from == to) continue;
    double lo = out.points[k].value, hi = out.points[k + 1].value;
    while (hi - lo > relative_width * std::max(std::abs(lo), std::abs(hi)) && hi - lo > 1e-300) {
      const double mid = lo + (hi - lo) / 2;
      if (mid <= lo || mid >= hi) break;
      // At the threshold itself eigenvalues pass through 0 and the verdict is degenerate; only
      // "same as the lower end or not" steers the bisection.
      if (at(mid).verdict == from) lo = mid;
      else hi = mid;
    }
    out.thresholds.push_back({lo + (hi - lo) / 2, lo, hi, from, to});
  }
  return out;
}

}  // namespace nhc
