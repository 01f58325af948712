#pragma once
/// \file design.hpp
/// \brief The design of an ensemble: which values each run gets. A grid (`--vary NAME=a:b:n`,
/// the Cartesian product of equally spaced values, the first variable varying slowest) or a
/// reproducible random sample (`--sample NAME=uniform(a,b)|normal(m,s) --samples N --seed S`).
///
/// Random values are a function of (seed, run, variable) only (a counter-based generator,
/// splitmix64; Steele, Lea & Flood, OOPSLA 2014): the same seed gives the same samples whatever
/// the number of ranks or threads, and N samples are the first N of any larger sample.

#include <cstdint>
#include <string>
#include <vector>

namespace nhc::ensemble {

/// One varied NAME and its values as the user wrote them.
struct VariableSpec {
  enum class Kind { grid, uniform, normal };
  std::string name;  ///< a parameter (`b`) or an initial value (`x'(0)`)
  std::string text;  ///< the flag's argument, for messages and the output file
  Kind kind = Kind::grid;
  double a = 0, b = 0;  ///< grid: from a to b; uniform: (a, b); normal: mean a, deviation b
  long n = 1;           ///< grid: number of values
};

/// `NAME=a:b:n` (flag `--vary`). Throws InputError naming the flag and the part that is wrong:
/// not NAME=a:b:n, not numbers, n < 1, an empty range (a = b with n > 1).
VariableSpec parse_vary(const std::string& text);
/// `NAME=uniform(a,b)` or `NAME=normal(m,s)` (flag `--sample`); a < b, s > 0.
VariableSpec parse_sample(const std::string& text);

struct Design {
  enum class Kind { grid, sample };
  Kind kind = Kind::grid;
  std::vector<VariableSpec> variables;
  std::vector<long> grid_shape;  ///< grid: n of each variable
  std::uint64_t seed = 0;        ///< sample
  long runs = 0;
  std::vector<double> values;  ///< runs × variables, row-major

  const double* row(long run) const { return values.data() + run * static_cast<long>(variables.size()); }
  std::vector<std::string> names() const;
};

/// The n values of a grid variable: a + (b − a) k/(n − 1), k = 0 … n−1 (a alone when n = 1).
std::vector<double> grid_values(const VariableSpec& spec);

/// The Cartesian product of the grid variables (distinct names; at most 10^9 runs, else
/// InputError on --vary).
Design make_grid(std::vector<VariableSpec> variables);
/// `samples` draws of every variable from `seed` (samples ≥ 1, else InputError on --samples).
Design make_sample(std::vector<VariableSpec> variables, long samples, std::uint64_t seed);

/// The counter-based generator: a uniform number in (0, 1) from (seed, run, stream).
double uniform_draw(std::uint64_t seed, std::uint64_t run, std::uint64_t stream);
/// Variable `variable` of run `run` (Box–Muller for normal()).
double sample_value(const VariableSpec& spec, std::uint64_t seed, long run, int variable);

}  // namespace nhc::ensemble
