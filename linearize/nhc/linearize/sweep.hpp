#pragma once
/// \file sweep.hpp
/// \brief The eigenvalues along a parameter or an initial value (`--sweep NAME=a:b:n`), and the
/// values where the stability verdict changes, refined by bisection (docs/linearize.md).

#include <string>
#include <vector>

#include "nhc/linearize/linearization.hpp"
#include "nhc/linearize/linearizer.hpp"

namespace nhc {

struct SweepRange {
  std::string name;
  double first = 0.0, last = 0.0;  ///< a and b, both included
  int count = 0;                   ///< n ≥ 2
};

/// Parses "NAME=a:b:n". Throws InputError (flag `flag`) unless a < b are finite and n ≥ 2 is an
/// integer.
SweepRange parse_sweep_range(const std::string& text, const std::string& flag = "--sweep");

struct SweepPoint {
  double value = 0.0;
  Linearization linearization;
};

struct VerdictChange {
  double value = 0.0;               ///< midpoint of the final bisection bracket
  double lower = 0.0, upper = 0.0;  ///< the bracket
  StabilityVerdict from = StabilityVerdict::unstable, to = StabilityVerdict::unstable;
};

struct SweepResult {
  SweepRange range;
  std::vector<SweepPoint> points;
  std::vector<VerdictChange> thresholds;
};

/// Linearizes at n equally spaced values of range.name (overrides applied first, then the
/// swept value), and bisects every interval whose end verdicts differ until its width is at
/// most `relative_width`·max(|lower|, |upper|). Throws like Linearizer::at, naming the value.
SweepResult sweep(const Linearizer& linearizer, const std::vector<PointOverride>& overrides, const SweepRange& range,
                  double relative_width = 1e-12);

}  // namespace nhc
