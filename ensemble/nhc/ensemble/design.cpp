// The ensemble's design: grid and random sample (design.hpp).
#include "nhc/ensemble/design.hpp"

#include <cmath>
#include <cstdlib>
#include <set>

#include "nhc/errors.hpp"

namespace nhc::ensemble {

namespace {

[[noreturn]] void bad(const std::string& flag, const std::string& text, const std::string& why) {
  throw InputError({flag + " " + text, 0, 0}, why);
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t") + 1 - b);
}

/// NAME and what follows '=' (both non-empty).
std::pair<std::string, std::string> split_name(const std::string& flag, const std::string& text,
                                               const std::string& form) {
  const auto eq = text.find('=');
  if (eq == std::string::npos) bad(flag, text, "expected " + form);
  std::string name = trim(text.substr(0, eq)), rest = trim(text.substr(eq + 1));
  if (name.empty()) bad(flag, text, "NAME before '=' is missing (expected " + form + ")");
  if (rest.empty()) bad(flag, text, "nothing after '=' (expected " + form + ")");
  return {name, rest};
}

double number(const std::string& flag, const std::string& text, const std::string& part, const char* what) {
  const std::string s = trim(part);
  char* end = nullptr;
  const double v = s.empty() ? NAN : std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v))
    bad(flag, text, std::string(what) + " '" + s + "' is not a finite number");
  return v;
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts;
  std::string::size_type start = 0, pos;
  while ((pos = s.find(sep, start)) != std::string::npos) {
    parts.push_back(s.substr(start, pos - start));
    start = pos + 1;
  }
  parts.push_back(s.substr(start));
  return parts;
}

void check_distinct(const std::vector<VariableSpec>& variables, const std::string& flag) {
  std::set<std::string> seen;
  for (const VariableSpec& v : variables)
    if (!seen.insert(v.name).second) bad(flag, v.text, "'" + v.name + "' is varied twice");
}

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

}  // namespace

VariableSpec parse_vary(const std::string& text) {
  const std::string flag = "--vary", form = "NAME=a:b:n";
  auto [name, range] = split_name(flag, text, form);
  const std::vector<std::string> parts = split(range, ':');
  if (parts.size() != 3) bad(flag, text, "expected " + form + " (from a to b in n values)");
  VariableSpec spec;
  spec.name = name;
  spec.text = text;
  spec.a = number(flag, text, parts[0], "a");
  spec.b = number(flag, text, parts[1], "b");
  const double n = number(flag, text, parts[2], "n");
  if (n != std::floor(n)) bad(flag, text, "n = " + trim(parts[2]) + " is not a whole number");
  if (n < 1) bad(flag, text, "n = " + trim(parts[2]) + " must be at least 1");
  if (n > 1e9) bad(flag, text, "n = " + trim(parts[2]) + " is more than 10^9 values");
  spec.n = static_cast<long>(n);
  if (spec.n > 1 && spec.a == spec.b)
    bad(flag, text, "the range " + trim(parts[0]) + ":" + trim(parts[1]) + " is empty (a = b with n > 1)");
  return spec;
}

VariableSpec parse_sample(const std::string& text) {
  const std::string flag = "--sample", form = "NAME=uniform(a,b) or NAME=normal(m,s)";
  auto [name, law] = split_name(flag, text, form);
  const auto open = law.find('(');
  if (open == std::string::npos || law.back() != ')') bad(flag, text, "expected " + form);
  const std::string kind = trim(law.substr(0, open));
  const std::vector<std::string> args = split(law.substr(open + 1, law.size() - open - 2), ',');
  VariableSpec spec;
  spec.name = name;
  spec.text = text;
  if (kind == "uniform") {
    spec.kind = VariableSpec::Kind::uniform;
  } else if (kind == "normal") {
    spec.kind = VariableSpec::Kind::normal;
  } else {
    bad(flag, text, "unknown distribution '" + kind + "' (uniform(a,b) or normal(m,s))");
  }
  if (args.size() != 2) bad(flag, text, kind + "() takes two numbers");
  const bool uniform = spec.kind == VariableSpec::Kind::uniform;
  spec.a = number(flag, text, args[0], uniform ? "a" : "m");
  spec.b = number(flag, text, args[1], uniform ? "b" : "s");
  if (uniform && !(spec.a < spec.b))
    bad(flag, text, "the range (" + trim(args[0]) + ", " + trim(args[1]) + ") is empty (need a < b)");
  if (!uniform && !(spec.b > 0)) bad(flag, text, "the deviation s = " + trim(args[1]) + " must be positive");
  return spec;
}

std::vector<std::string> Design::names() const {
  std::vector<std::string> out;
  for (const VariableSpec& v : variables) out.push_back(v.name);
  return out;
}

std::vector<double> grid_values(const VariableSpec& spec) {
  std::vector<double> v(static_cast<std::size_t>(spec.n));
  for (long k = 0; k < spec.n; ++k)
    v[static_cast<std::size_t>(k)] = spec.n == 1 ? spec.a
                                     : k == spec.n - 1
                                         ? spec.b
                                         : spec.a + (spec.b - spec.a) * static_cast<double>(k) / (spec.n - 1);
  return v;
}

Design make_grid(std::vector<VariableSpec> variables) {
  check_distinct(variables, "--vary");
  Design d;
  d.kind = Design::Kind::grid;
  d.variables = std::move(variables);
  double total = 1;
  for (const VariableSpec& v : d.variables) {
    d.grid_shape.push_back(v.n);
    total *= static_cast<double>(v.n);
  }
  if (total > 1e9) bad("--vary", d.variables.back().text, "the grid has more than 10^9 runs");
  d.runs = static_cast<long>(total);
  const std::size_t nv = d.variables.size();
  std::vector<std::vector<double>> axes;
  for (const VariableSpec& v : d.variables) axes.push_back(grid_values(v));
  d.values.resize(static_cast<std::size_t>(d.runs) * nv);
  for (long run = 0; run < d.runs; ++run) {
    long rest = run;  // the last variable varies fastest (row-major, numpy's reshape(grid_shape))
    for (std::size_t j = nv; j-- > 0;) {
      const long n = d.grid_shape[j];
      d.values[static_cast<std::size_t>(run) * nv + j] = axes[j][static_cast<std::size_t>(rest % n)];
      rest /= n;
    }
  }
  return d;
}

double uniform_draw(std::uint64_t seed, std::uint64_t run, std::uint64_t stream) {
  const std::uint64_t x = splitmix64(splitmix64(splitmix64(seed) ^ run) ^ stream);
  return (static_cast<double>(x >> 11) + 0.5) * 0x1.0p-53;  // in (0, 1), never 0 or 1
}

double sample_value(const VariableSpec& spec, std::uint64_t seed, long run, int variable) {
  const auto r = static_cast<std::uint64_t>(run);
  const auto stream = 2 * static_cast<std::uint64_t>(variable);
  const double u1 = uniform_draw(seed, r, stream);
  if (spec.kind == VariableSpec::Kind::uniform) return spec.a + (spec.b - spec.a) * u1;
  const double u2 = uniform_draw(seed, r, stream + 1);
  return spec.a + spec.b * std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);  // Box–Muller
}

Design make_sample(std::vector<VariableSpec> variables, long samples, std::uint64_t seed) {
  check_distinct(variables, "--sample");
  if (samples < 1) throw InputError({"--samples " + std::to_string(samples), 0, 0}, "N must be at least 1");
  if (samples > 1000000000L) throw InputError({"--samples " + std::to_string(samples), 0, 0}, "more than 10^9 runs");
  Design d;
  d.kind = Design::Kind::sample;
  d.variables = std::move(variables);
  d.seed = seed;
  d.runs = samples;
  const std::size_t nv = d.variables.size();
  d.values.resize(static_cast<std::size_t>(samples) * nv);
  for (long run = 0; run < samples; ++run)
    for (std::size_t j = 0; j < nv; ++j)
      d.values[static_cast<std::size_t>(run) * nv + j] = sample_value(d.variables[j], seed, run, static_cast<int>(j));
  return d;
}

}  // namespace nhc::ensemble
