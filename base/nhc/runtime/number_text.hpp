#pragma once
/// \file number_text.hpp
/// \brief A number in the runtime's messages: `significant` digits in the stream's shortest form
/// (1e-08, 0.25, 631.04). One helper for every message that names a time, a tolerance or a value.

#include <sstream>
#include <string>

namespace nhc::runtime {

inline std::string number_text(double value, int significant) {
  std::ostringstream os;
  os.precision(significant);
  os << value;
  return os.str();
}

}  // namespace nhc::runtime
