#include "error_translation.hpp"

#include <new>
#include <string>

#include "nhc/errors.hpp"
#include "nhc/base/errors.hpp"

namespace py = pybind11;

namespace nhc::python {

namespace {

/// Raises nhc.errors.<name>(message, **attributes).
void raise(const char* name, const std::string& message, const py::dict& attributes = py::dict()) {
  const py::object type = py::module_::import("nhc.errors").attr(name);
  const py::object error = type(message, **attributes);
  PyErr_SetObject(type.ptr(), error.ptr());
}

}  // namespace

void register_errors(py::module_&) {
  py::register_exception_translator([](std::exception_ptr failure) {
    if (!failure) return;
    try {
      std::rethrow_exception(failure);
    } catch (const InputError& e) {
      py::dict where;
      where["file"] = e.where().file;
      where["line"] = e.where().line;
      where["column"] = e.where().column;
      raise("SceneError", e.what(), where);
    } catch (const WorkLimitExceeded& e) {
      raise("SceneError", std::string("the scene needs too much work: ") + e.what());
    } catch (const base::SolverError& e) {
      py::dict at;
      at["t"] = e.t();
      raise("MathError", e.what(), at);
    } catch (const MathError& e) {
      raise("MathError", e.what());
    } catch (const EnvironmentError& e) {
      raise("HostError", e.what());
    } catch (const std::bad_alloc&) {
      raise("HostError", "out of memory");
    } catch (const py::error_already_set&) {
      throw;  // a Python exception (KeyboardInterrupt, one raised by a callback): itself
    } catch (const py::builtin_exception&) {
      throw;  // pybind11's own (TypeError of a callback's result, cast errors)
    } catch (const std::exception& e) {
      // What the command line calls an internal error (exit 1): still an nhc.Error, never a raw
      // RuntimeError from GiNaC or a std::length_error.
      raise("Error", std::string("internal error: ") + e.what() +
                         " (this is a bug in nhc; please report it with the call and the scene)");
    }
  });
}

}  // namespace nhc::python
