#pragma once
/// \file number_text.hpp
/// \brief The one formatter of numbers in nhc's messages and text output: `significant` digits in
/// the shortest of fixed and scientific notation (1e-08, 0.25, 631.04), as printf's %g and an
/// std::ostream's default notation print them: a person reads a few digits, without trailing zeros;
/// and the shortest text that reads back as the same double, for data that programs read back
/// (CSV, gnuplot data, tables), which keeps every bit without the noise digits of a fixed 17.

#include <fmt/format.h>

#include <iterator>
#include <string>

namespace nhc::base {

inline std::string number_text(double value, int significant) { return fmt::format("{:.{}g}", value, significant); }

/// The shortest text that reads back as exactly `value` (0.1, 1e-08, 0.30000000000000004; nan,
/// inf): data files keep every bit without the noise digits of a fixed 17.
inline std::string shortest_text(double value) { return fmt::format("{}", value); }

/// `separator` and shortest_text(value) appended to `text`, without a temporary string (the rows
/// of a CSV of thousands of columns).
inline void append_shortest(std::string& text, char separator, double value) {
  text += separator;
  fmt::format_to(std::back_inserter(text), "{}", value);
}

}  // namespace nhc::base
