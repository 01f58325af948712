// Dynamic load balancing over threads and MPI ranks (scheduler.hpp).
#include "nhc/ensemble/scheduler.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <system_error>
#include <thread>

#ifdef NHC_HAVE_MPI
#include <mpi.h>
#endif

namespace nhc::ensemble {

Dispenser::Dispenser(std::vector<std::int64_t> todo, int workers)
    : todo_(std::move(todo)), workers_(std::max(1, workers)) {}

std::vector<std::int64_t> Dispenser::next() {
  const std::lock_guard<std::mutex> lock(mutex_);
  const std::size_t remaining = todo_.size() - position_;
  const std::size_t guided =
      (remaining + 2 * static_cast<std::size_t>(workers_) - 1) / (2 * static_cast<std::size_t>(workers_));
  const std::size_t n = std::min<std::size_t>(remaining, std::clamp<std::size_t>(guided, 1, kMaxChunk));
  std::vector<std::int64_t> chunk(todo_.begin() + static_cast<long>(position_),
                                  todo_.begin() + static_cast<long>(position_ + n));
  position_ += n;
  return chunk;
}

namespace {

using namespace std::chrono_literals;

/// Records made by root's worker threads, waiting for its main thread.
class Inbox {
 public:
  /// Not a wake-up of the main thread per record: on a busy machine each wake-up can cost the
  /// worker its time slice. The main thread collects every 20 ms.
  void add(RunRecord&& r) {
    const std::lock_guard<std::mutex> lock(mutex_);
    records_.push_back(std::move(r));
  }
  /// A worker thread has ended: wakes the main thread.
  void worker_done() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      ++done_;
    }
    arrived_.notify_one();
  }
  /// Waits until a worker ends or `timeout` passes.
  void wait(std::chrono::milliseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    arrived_.wait_for(lock, timeout, [&] { return done_ != seen_done_; });
    seen_done_ = done_;
  }
  std::vector<RunRecord> take() {
    const std::lock_guard<std::mutex> lock(mutex_);
    return std::move(records_);
  }

 private:
  std::mutex mutex_;
  std::condition_variable arrived_;
  std::vector<RunRecord> records_;
  int done_ = 0, seen_done_ = 0;
};

/// Root's worker threads: each takes chunks from the dispenser until it is empty.
class LocalWorkers {
 public:
  LocalWorkers(int threads, Dispenser& dispenser, const RunFunction& run, const ScheduleOptions& options, int rank,
               Inbox& inbox) {
    running_ = threads;
    for (int k = 0; k < threads; ++k) {
      try {
        threads_.emplace_back([&, rank] {
          for (std::vector<std::int64_t> chunk; !(chunk = dispenser.next()).empty();)
            for (std::int64_t i : chunk) {
              RunRecord r = run(i, options.values(i));
              r.rank = rank;
              inbox.add(std::move(r));
            }
          --running_;
          inbox.worker_done();
        });
      } catch (const std::system_error&) {
        // The machine gives no more threads (a ulimit): the ones started do the work; with
        // none, the caller hears why (an exception escaping with threads joinable would abort).
        running_ -= threads - k;
        if (k == 0) throw;
        break;
      }
    }
  }
  ~LocalWorkers() { join(); }
  bool running() const { return running_ > 0; }
  void join() {
    for (std::thread& t : threads_)
      if (t.joinable()) t.join();
  }

 private:
  std::atomic<int> running_{0};
  std::vector<std::thread> threads_;
};

void deliver(Inbox& inbox, const ScheduleOptions& options) {
  std::vector<RunRecord> records = inbox.take();
  if (!records.empty()) options.on_records(std::move(records));
}

void schedule_threads(std::vector<std::int64_t> todo, const RunFunction& run, const ScheduleOptions& options) {
  const int threads = std::max(1, options.threads);
  Dispenser dispenser(std::move(todo), threads);
  Inbox inbox;
  LocalWorkers workers(threads, dispenser, run, options, 0, inbox);
  while (workers.running()) {
    inbox.wait(20ms);
    deliver(inbox, options);
    options.on_idle();
  }
  workers.join();
  deliver(inbox, options);
}

#ifdef NHC_HAVE_MPI

/// Worker → root: kRequest asks for a chunk, kDone carries one finished run's record.
/// Root → worker: kWork is a chunk, kStop ends the worker. MPI keeps the messages of one
/// sender in order, so every kDone of a worker arrives before its last kRequest.
enum Tag : int { kRequest = 1, kWork = 2, kStop = 3, kDone = 4 };

/// Waits for a message without MPI's busy polling (which would take a core from the worker
/// threads when ranks share a machine): probe, then sleep a little longer each time.
MPI_Status wait_for_message(int source, int tag) {
  MPI_Status status;
  auto pause = 2us;
  for (;;) {
    int flag = 0;
    MPI_Iprobe(source, tag, MPI_COMM_WORLD, &flag, &status);
    if (flag) return status;
    std::this_thread::sleep_for(pause);
    pause = std::min<std::chrono::microseconds>(2 * pause, 200us);
  }
}

std::vector<char> receive(const MPI_Status& status) {
  int count = 0;
  MPI_Get_count(&status, MPI_BYTE, &count);
  std::vector<char> bytes(static_cast<std::size_t>(count));
  MPI_Recv(bytes.data(), count, MPI_BYTE, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return bytes;
}

void send(std::vector<char>& bytes, int destination, int tag) {
  MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, destination, tag, MPI_COMM_WORLD);
}

/// Rank 0: answers the workers, runs its own share on a thread, delivers everything.
void manage(const Session& session, std::vector<std::int64_t> todo, const RunFunction& run,
            const ScheduleOptions& options) {
  const int remote = session.size() - 1;
  Dispenser dispenser(std::move(todo), remote + 1);
  Inbox inbox;
  LocalWorkers local(1, dispenser, run, options, 0, inbox);
  int active = remote;
  auto last_idle = std::chrono::steady_clock::now();
  auto pause = 10us;  // grows while nothing arrives: few wake-ups that would take the worker thread's core
  while (active > 0 || local.running()) {
    int flag = 0;
    MPI_Status status;
    // Any tag: a worker's records (kDone) are taken in the order it sent them, before its request.
    MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status);
    if (flag && status.MPI_TAG == kDone) {
      const std::vector<char> bytes = receive(status);
      ByteReader in(bytes);
      std::vector<RunRecord> records;
      while (!in.done()) records.push_back(decode_record(in));
      if (!records.empty()) options.on_records(std::move(records));
      pause = 10us;
      continue;
    }
    if (flag) {
      receive(status);  // kRequest: empty
      const std::vector<std::int64_t> chunk = dispenser.next();
      ByteWriter work;
      work.put<std::uint64_t>(chunk.size());
      for (std::int64_t i : chunk) {
        work.put(i);
        const double* v = options.values(i);
        for (int k = 0; k < options.values_per_run; ++k) work.put(v[k]);
      }
      send(work.bytes(), status.MPI_SOURCE, chunk.empty() ? kStop : kWork);
      if (chunk.empty()) --active;
      pause = 10us;
      continue;  // answer every waiting worker before anything else
    }
    deliver(inbox, options);
    if (std::chrono::steady_clock::now() - last_idle > 20ms) {
      options.on_idle();
      last_idle = std::chrono::steady_clock::now();
    }
    std::this_thread::sleep_for(pause);
    pause = std::min<std::chrono::microseconds>(2 * pause, 500us);
  }
  local.join();
  deliver(inbox, options);
}

/// Ranks > 0: ask for a chunk, run it, until told to stop. Each finished run's record goes to
/// root at once (a killed rank loses only the run it was doing, not the rest of its chunk; root
/// checkpoints what arrived).
void work(const Session& session, const RunFunction& run, const ScheduleOptions& options) {
  for (;;) {
    std::vector<char> request;
    send(request, 0, kRequest);
    const MPI_Status status = wait_for_message(0, MPI_ANY_TAG);
    const std::vector<char> bytes = receive(status);
    if (status.MPI_TAG == kStop) return;
    ByteReader in(bytes);
    const auto n = in.get<std::uint64_t>();
    std::vector<double> values;
    for (std::uint64_t k = 0; k < n; ++k) {
      const auto index = in.get<std::int64_t>();
      values.resize(static_cast<std::size_t>(options.values_per_run));
      for (double& v : values) v = in.get<double>();
      RunRecord r = run(index, values.data());
      r.rank = session.rank();
      ByteWriter record;
      encode(record, r);
      send(record.bytes(), 0, kDone);
    }
  }
}

#endif

}  // namespace

void schedule(const Session& session, std::vector<std::int64_t> todo, const RunFunction& run,
              const ScheduleOptions& options) {
#ifdef NHC_HAVE_MPI
  if (session.uses_mpi() && session.size() > 1) {
    if (session.is_root()) manage(session, std::move(todo), run, options);
    else work(session, run, options);
    return;
  }
#endif
  (void)session;
  if (session.is_root()) schedule_threads(std::move(todo), run, options);
}

}  // namespace nhc::ensemble
