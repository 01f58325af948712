#pragma once
/// \file primed_name.hpp
/// \brief The one spelling of a derivative by name: x, x', x'' (order primes after the name), as
/// scenes write derivatives and every column, flag and message names them.

#include <cstddef>
#include <string>

namespace nhc::base {

inline std::string primed_name(const std::string& name, int order) {
  return name + std::string(static_cast<std::size_t>(order), '\'');
}

}  // namespace nhc::base
