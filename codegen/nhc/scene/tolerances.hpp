#pragma once
/// \file tolerances.hpp
/// \brief Tolerances the arithmetic can honour. IDA's error test asks the local error of each
/// state y to stay below rtol·|y| + atol; in double precision y itself is only known to its
/// unit roundoff (2^-53 ≈ 1.1e-16, relative), so a relative tolerance below the machine epsilon
/// 2^-52 ≈ 2.2e-16 asks for more digits than a double holds: the run would grind through tiny
/// steps and fail with a misleading "error test failed" instead.

#include <cfloat>
#include <cmath>
#include <string>

namespace nhc {

inline constexpr double kSmallestRelativeTolerance = DBL_EPSILON;

/// Why `rtol` cannot be used as a relative tolerance; empty when it can.
inline std::string relative_tolerance_problem(double rtol) {
  if (!(std::isfinite(rtol) && rtol > 0)) return "must be a positive number";
  if (rtol < kSmallestRelativeTolerance)
    return "is below the double-precision machine epsilon 2.2e-16: no arithmetic in doubles can honour it "
           "(use at least 1e-15)";
  // An error as large as the state itself: not one correct digit is asked for.
  if (rtol >= 1) return "is not below 1: a relative tolerance of 1 or more asks for no correct digit";
  return {};
}

}  // namespace nhc
