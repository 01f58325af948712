#include "nhc/errors.hpp"

#include <string>

namespace nhc {

std::string SourceLocation::str() const {
  if (line <= 0) return file;
  return file + ":" + std::to_string(line) + ":" + std::to_string(column > 0 ? column : 1);
}

InputError::InputError(SourceLocation where, const std::string& message)
    : std::runtime_error(where.str() + ": error: " + message), where_(std::move(where)), message_(message) {}

}  // namespace nhc
