#pragma once
/// \file errors.hpp
/// \brief The kinds of failure nhc reports to users, and their exit codes.
///
/// InputError: the user's input is wrong (scene file, flag); exit code 2, one line
/// `FILE:LINE:COLUMN: error: message`.
/// MathError: the input is well formed but the mathematics fails (a singular matrix,
/// a structurally singular system, an integrator failure); exit code 3.
/// EnvironmentError: the machine around nhc fails it (a file cannot be written, the disk is
/// full, the C++ compiler is missing, fails or times out, a library cannot be loaded, the
/// compile cache is unusable); exit code 4. The message names the path and the system's reason.

#include <stdexcept>
#include <string>

namespace nhc {

/// Where in a source file something is; line and column are 1-based, 0 when unknown.
struct SourceLocation {
  std::string file;
  int line = 0;
  int column = 0;

  /// "FILE:LINE:COLUMN", or "FILE" when the position is unknown.
  std::string str() const;
};

class InputError : public std::runtime_error {
 public:
  InputError(SourceLocation where, const std::string& message);
  const SourceLocation& where() const noexcept { return where_; }
  const std::string& message() const noexcept { return message_; }

 private:
  SourceLocation where_;
  std::string message_;
};

class MathError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class EnvironmentError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline constexpr int kExitOk = 0;
inline constexpr int kExitInternal = 1;
inline constexpr int kExitBadInput = 2;
inline constexpr int kExitMathFailure = 3;
inline constexpr int kExitEnvironment = 4;

}  // namespace nhc
