#pragma once
/// \file scheduler.hpp
/// \brief Dynamic load balancing of an ensemble's runs. Runs differ a lot in cost (some stop
/// early at a singular point), so runs are handed out in chunks as workers become free, the
/// chunks shrinking as the work runs out (guided self-scheduling; Polychronopoulos & Kuck,
/// IEEE Trans. Comput. 36 (1987) 1425): chunk = ceil(remaining / (2 workers)), at most
/// kMaxChunk.
///
/// In one process the workers are threads. Under MPI, rank 0 is the manager: its main thread
/// answers the other ranks (MPI_Send/MPI_Recv: a worker asks for a chunk and sends each run's
/// record as soon as the run ends) while its own worker thread runs too; every record arrives at
/// rank 0, and a checkpoint there keeps every run a killed rank had finished.

#include <cstdint>
#include <functional>
#include <mutex>
#include <vector>

#include "nhc/ensemble/run.hpp"
#include "nhc/ensemble/session.hpp"

namespace nhc::ensemble {

inline constexpr long kMaxChunk = 256;

/// The runs still to do, handed out in guided chunks. Thread-safe.
class Dispenser {
 public:
  Dispenser(std::vector<std::int64_t> todo, int workers);
  /// The next chunk of run indices; empty when everything is handed out.
  std::vector<std::int64_t> next();

 private:
  std::mutex mutex_;
  std::vector<std::int64_t> todo_;
  std::size_t position_ = 0;
  int workers_;
};

/// Runs one design row. Called concurrently from several threads: it must not share mutable
/// state (run_one() with a shared Model and RunSpec does not).
using RunFunction = std::function<RunRecord(std::int64_t index, const double* values)>;

struct ScheduleOptions {
  /// Worker threads in a process without MPI; under MPI every rank runs one run at a time.
  int threads = 1;
  /// Values of a run (root only): a row of the design.
  std::function<const double*(std::int64_t index)> values;
  int values_per_run = 0;
  /// Called on root's main thread with records as they arrive, in no particular order.
  std::function<void(std::vector<RunRecord>&&)> on_records;
  /// Called on root's main thread between arrivals (at least every 50 ms): progress, checkpoints.
  std::function<void()> on_idle;
};

/// Runs `todo` (root's list; ignored on the other ranks) over the session's ranks and threads.
/// Returns on every rank when all runs are done and their records delivered to on_records.
void schedule(const Session& session, std::vector<std::int64_t> todo, const RunFunction& run,
              const ScheduleOptions& options);

}  // namespace nhc::ensemble
