#pragma once
/// \file errors.hpp
/// \brief The four kinds of failure the library reports to its callers; the nhc command maps
/// each to its exit code (cli/exit_codes.hpp).
///
/// InputError (exit 2): the user's input is wrong (a scene file); it carries the position, and
/// what() is one line `FILE:LINE:COLUMN: error: message`.
/// MathError (exit 3): the input is well formed but the mathematics fails (a singular matrix,
/// a structurally singular system, a model that does not apply).
/// WorkLimitExceeded: the input is well formed but a symbolic operation on it would exceed the
/// work budget (nhc/expr/work_budget.hpp). It is bad input (exit 2): the layers that know where
/// the expression came from turn it into an InputError at that place (located()).
/// EnvironmentError (exit 4): the machine around nhc fails it (a file cannot be written, the disk
/// is full, the C++ compiler is missing, fails or times out, a library cannot be loaded, the
/// compile cache is unusable); the message names the path and the system's reason.

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

class WorkLimitExceeded : public std::runtime_error {
 public:
  /// `what_grew`: what the operation would have produced ("expanding it would give … terms").
  explicit WorkLimitExceeded(const std::string& what_grew) : std::runtime_error(what_grew) {}
  /// The refusal as an InputError at `where`, naming the work ("deriving the chetaev model").
  InputError located(const SourceLocation& where, const std::string& work) const {
    return InputError(where, work + " needs too much work: " + what());
  }
};

/// f(); a WorkLimitExceeded from it becomes an InputError at `where` naming the `work`: how the
/// layers that know the scene locate a refusal of the work budget.
template <class F>
decltype(auto) refusing_at(const SourceLocation& where, const std::string& work, F&& f) {
  try {
    return f();
  } catch (const WorkLimitExceeded& e) {
    throw e.located(where, work);
  }
}

class EnvironmentError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace nhc
