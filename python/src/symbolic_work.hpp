#pragma once
/// \file symbolic_work.hpp
/// \brief How the module calls the library's symbolic work (loading, deriving, analysing,
/// building, linearizing): with the GIL held, which makes it safe from several Python threads,
/// and interruptible by Ctrl-C.
///
/// GiNaC's reference counts are plain integers and the memo tables of Intermediate
/// (nhc/expr/intermediate.hpp) have no locks, and GiNaC objects are also created and destroyed
/// with the GIL held (a Scene's expressions, its Python object's end): the one lock every such
/// place already holds is the GIL, so symbolic work keeps it. It lets it go only while the work
/// waits for the compiler (no GiNaC object is touched then), so that Python's other threads run.
/// Numeric runs let it go; symbolic work they reach (an [events] expression that GiNaC evaluates)
/// takes it back through the library's symbolic lock (nhc/long_work.hpp), which is the GIL here.

#include <pybind11/pybind11.h>

#include <atomic>
#include <optional>
#include <thread>
#include <vector>

#include "nhc/errors.hpp"
#include "nhc/expr/work_stage.hpp"
#include "nhc/long_work.hpp"

namespace nhc::python {

/// Processor seconds of symbolic work one call from Python may spend (nhc.set_work_limit; the
/// command line's default, work_stage.hpp).
double& work_limit_seconds();

/// The observer (nhc/long_work.hpp) of one call from Python: a signal pending in Python (Ctrl-C)
/// stops the work, and so does the work budget (the command line's --work-limit, asked at the
/// work's stop questions); the GIL is released while the work waits for the compiler.
class PythonCallObserver final : public LongWorkObserver {
 public:
  bool stop_requested() override {
    if (stopped_) return true;
    if (std::this_thread::get_id() != owner_) return false;  // the compiler threads: the caller decides
    if (limit_.exceeded()) return stopped_ = true;
    if (released_) {
      pybind11::gil_scoped_acquire locked;
      check_signals();
    } else {
      check_signals();
    }
    return stopped_;
  }
  void waiting_begins() override {
    if (std::this_thread::get_id() == owner_ && depth_++ == 0) released_.emplace();
  }
  void waiting_ends() override {
    if (std::this_thread::get_id() == owner_ && --depth_ == 0) released_.reset();
  }
  /// The Python exception the signal handler raised (KeyboardInterrupt), with the GIL held.
  [[noreturn]] void raise() {
    if (error_) throw std::move(*error_);
    if (limit_.exceeded())  // nhc.SceneError, as the command line's exit 2
      throw InputError({limit_.scene_path().empty() ? "nhc" : limit_.scene_path()},
                       limit_.message("raise the limit with nhc.set_work_limit(seconds)"));
    throw pybind11::error_already_set();
  }

 private:
  void check_signals() {
    if (PyErr_CheckSignals() == 0) return;
    error_.emplace();  // fetches the raised exception
    stopped_ = true;
  }

  const std::thread::id owner_ = std::this_thread::get_id();
  work_budget::ProcessorTimeLimit limit_{work_limit_seconds()};
  std::atomic<bool> stopped_{false};
  int depth_ = 0;
  std::optional<pybind11::gil_scoped_release> released_;
  std::optional<pybind11::error_already_set> error_;
};

/// The module's symbolic lock (nhc/long_work.hpp): the GIL, taken again by a thread that let it
/// go for a numeric run (PyGILState_Ensure nests, so a thread holding it may take it too).
class GilSymbolicLock final : public SymbolicLock {
 public:
  void lock() override { states().push_back(PyGILState_Ensure()); }
  void unlock() override {
    const PyGILState_STATE state = states().back();
    states().pop_back();
    PyGILState_Release(state);
  }

 private:
  static std::vector<PyGILState_STATE>& states() {
    thread_local std::vector<PyGILState_STATE> taken;
    return taken;
  }
};

/// f() as symbolic work: with the GIL (called with it), interruptible.
template <class F>
auto symbolic_work(F&& f) -> decltype(f()) {
  PythonCallObserver observer;
  try {
    const ObservedWork observed(observer);
    return f();
  } catch (const WorkInterrupted&) {
    observer.raise();
  }
}

}  // namespace nhc::python
