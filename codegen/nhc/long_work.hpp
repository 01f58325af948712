#pragma once
/// \file long_work.hpp
/// \brief Long work (derivation, generation, the compiler's run) asks its caller, through an
/// observer the caller installs for its thread, whether to stop, and tells it when it only waits
/// for another process. The command line needs neither (its signal handler ends the process); an
/// interpreter does: Python's Ctrl-C is raised only when the module asks for it, and Python's
/// other threads may run while nhc waits for the compiler.

namespace nhc {

/// Thrown out of long work when the observer asked for a stop. Not a std::exception: the
/// handlers that turn a failed numeric attempt into a fallback (catch std::exception) let it pass.
class WorkInterrupted {};

class LongWorkObserver {
 public:
  virtual ~LongWorkObserver() = default;
  /// Asked at most every kStopCheckMilliseconds of work, from the thread that installed the
  /// observer or from threads the work started; true ends the work with WorkInterrupted.
  virtual bool stop_requested() = 0;
  /// The work waits for other processes (the compiler) until waiting_ends(); nested pairs and
  /// pairs from the work's other threads may come.
  virtual void waiting_begins() {}
  virtual void waiting_ends() {}
};

/// Installs an observer for this thread's work while it lives (the previous one after).
class ObservedWork {
 public:
  explicit ObservedWork(LongWorkObserver& observer);
  ~ObservedWork();
  ObservedWork(const ObservedWork&) = delete;
  ObservedWork& operator=(const ObservedWork&) = delete;

 private:
  LongWorkObserver* previous_;
};

/// This thread's observer, or null: for work that spreads over threads (each installs it).
LongWorkObserver* current_observer();

/// The longest stretch of work between two questions to the observer, in milliseconds.
inline constexpr int kStopCheckMilliseconds = 20;

/// Throws WorkInterrupted when this thread's observer asks for a stop; asks it at most every
/// kStopCheckMilliseconds (a clock read otherwise), nothing without an observer.
void check_for_stop();
/// check_for_stop() now, without the interval.
void check_for_stop_now();

/// The lock that symbolic work (GiNaC) holds: GiNaC's reference counts and Intermediate's memo
/// tables are not synchronised, so one thread at a time may do it. A caller whose threads do
/// symbolic work installs the lock they share (Python's module: the GIL, python/src/symbolic_work.hpp);
/// the command line has none.
class SymbolicLock {
 public:
  virtual ~SymbolicLock() = default;
  virtual void lock() = 0;
  virtual void unlock() = 0;
};

/// Installs the process's symbolic lock (null: none, the default).
void set_symbolic_lock(SymbolicLock* lock);

/// Holds the symbolic lock while it lives: symbolic work reached from numeric work that runs
/// without it (an [events] expression GiNaC evaluates during a run, app/sample_expressions.hpp).
class SymbolicSection {
 public:
  SymbolicSection();
  ~SymbolicSection();
  SymbolicSection(const SymbolicSection&) = delete;
  SymbolicSection& operator=(const SymbolicSection&) = delete;

 private:
  SymbolicLock* lock_;
};

/// The work waits for another process while this lives (waiting_begins / waiting_ends).
class WaitingForProcess {
 public:
  WaitingForProcess();
  ~WaitingForProcess();
  WaitingForProcess(const WaitingForProcess&) = delete;
  WaitingForProcess& operator=(const WaitingForProcess&) = delete;

 private:
  LongWorkObserver* observer_;
};

}  // namespace nhc
