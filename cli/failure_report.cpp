#include "failure_report.hpp"

#include <iostream>
#include <new>
#include <system_error>

#include "exit_codes.hpp"
#include "nhc/errors.hpp"

namespace nhc::cli {

namespace {

/// Resources the machine may refuse: the environment's doing, not a bug (std::thread reports
/// EAGAIN as a std::system_error under a ulimit).
bool refused_resource(const std::error_code& c) {
  return c == std::errc::resource_unavailable_try_again || c == std::errc::not_enough_memory ||
         c == std::errc::too_many_files_open || c == std::errc::too_many_files_open_in_system ||
         c == std::errc::no_space_on_device;
}

int internal(const char* what) {
  std::cerr << "nhc: internal error: " << what << "\n"
            << "nhc: this is a bug in nhc; please report it with the command and the scene\n";
  return kExitInternal;
}

}  // namespace

int report_failure(std::exception_ptr failure) {
  try {
    std::rethrow_exception(failure);
  } catch (const InputError& e) {
    std::cerr << e.what() << "\n";
    return kExitBadInput;
  } catch (const WorkLimitExceeded& e) {
    // Not located by a layer that knows the scene: still bad input, named as such.
    std::cerr << "nhc: error: the scene needs too much work: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const MathError& e) {
    std::cerr << "nhc: error: " << e.what() << "\n";
    return kExitMathFailure;
  } catch (const EnvironmentError& e) {
    std::cerr << "nhc: error: " << e.what() << "\n";
    return kExitEnvironment;
  } catch (const std::bad_alloc&) {
    std::cerr << "nhc: error: out of memory\n";
    return kExitEnvironment;
  } catch (const std::system_error& e) {
    if (!refused_resource(e.code())) return internal(e.what());
    std::cerr << "nhc: error: the machine refused a resource: " << e.what()
              << " (free memory or processes, raise the limits, or ask for fewer --threads)\n";
    return kExitEnvironment;
  } catch (const std::exception& e) {
    return internal(e.what());
  } catch (...) {
    return internal("an exception that is not a std::exception");
  }
}

}  // namespace nhc::cli
