#pragma once
/// \file number_text.hpp
/// \brief The one formatter of numbers in nhc's messages and text output: `significant` digits in
/// the shortest of fixed and scientific notation (1e-08, 0.25, 631.04), as printf's %g, which is
/// what the messages had written with std::ostream precision, so that they read as before.

#include <fmt/format.h>

#include <string>

namespace nhc::runtime {

inline std::string number_text(double value, int significant) {
  return fmt::format("{:.{}g}", value, significant);
}

}  // namespace nhc::runtime
