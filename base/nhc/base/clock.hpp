#pragma once
/// \file clock.hpp
/// \brief The clock of the timings nhc reports (build, integration, reading inputs): a steady
/// clock, so that a change of the system's time during a run does not enter a measured duration.

#include <chrono>

namespace nhc::base {

using Clock = std::chrono::steady_clock;

/// Seconds from `start` to now.
inline double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace nhc::base
