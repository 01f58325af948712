// Under `mpirun -np 2`: a worker rank's finished runs reach rank 0 one by one, not at the end of
// its chunk (before, a killed rank lost up to kMaxChunk runs the checkpoint could have
// kept). Rank 1's third run waits until rank 0 has received the records of its first two; with
// records sent per chunk they would only arrive after that run, so the wait would time out. Rank
// 0's own worker thread waits for rank 1's first record before its first run, so rank 1 surely
// gets a chunk of several runs (no timing is assumed; the waits only bound a failure).
// Usage: mpirun -np 2 nhc_mpi_records_per_run MARKER_FILE   (exit 0: pass)
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <thread>
#include <vector>

#include "nhc/ensemble/scheduler.hpp"
#include "nhc/ensemble/session.hpp"

namespace ne = nhc::ensemble;
using namespace std::chrono_literals;

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  const std::filesystem::path marker = argv[1];
  ne::Session session;
  if (!session.uses_mpi() || session.size() != 2) {
    std::fprintf(stderr, "run under mpirun -np 2\n");
    return 2;
  }
  if (session.is_root()) std::filesystem::remove(marker);
  session.broadcast(0);  // the marker is gone before any run starts

  // 100 runs in guided chunks of ceil(remaining / 4): rank 1's first chunk holds at least 19.
  std::vector<std::int64_t> todo;
  for (std::int64_t i = 0; i < 100; ++i) todo.push_back(i);
  const double value = 0;
  int runs_here = 0;  // on each rank, its worker's runs (rank 0: one worker thread)
  bool waited_out = false;
  std::atomic<int> from_rank_1{0};
  const auto wait_for = [](const auto& condition) {
    const auto deadline = std::chrono::steady_clock::now() + 120s;
    while (!condition() && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(10ms);
    return condition();
  };
  const ne::RunFunction run = [&](std::int64_t index, const double*) {
    ++runs_here;
    if (session.rank() == 1 && runs_here == 3) waited_out = !wait_for([&] { return std::filesystem::exists(marker); });
    if (session.rank() == 0 && runs_here == 1) wait_for([&] { return from_rank_1.load() > 0; });
    ne::RunRecord r;
    r.index = index;
    r.outcome = ne::Outcome::ok;
    return r;
  };
  long delivered = 0;
  bool marked = false;
  ne::ScheduleOptions options;
  options.values = [&](std::int64_t) { return &value; };
  options.values_per_run = 0;
  options.on_records = [&](std::vector<ne::RunRecord>&& records) {
    for (const ne::RunRecord& r : records) {
      ++delivered;
      if (r.rank == 1 && ++from_rank_1 >= 2 && !marked) {
        std::ofstream(marker) << "rank 0 has two of rank 1's records\n";
        marked = true;
      }
    }
  };
  options.on_idle = [] {};
  ne::schedule(session, todo, run, options);
  if (session.rank() == 1 && waited_out) {
    std::fprintf(stderr, "FAIL: rank 1's first records did not reach rank 0 while its chunk was running\n");
    session.abort(1);
  }
  if (session.is_root()) {
    if (delivered != 100 || !marked) {
      std::fprintf(stderr, "FAIL: %ld of 100 records delivered, rank 1 ran %s\n", delivered,
                   marked ? "at least 2" : "fewer than 2");
      return 1;
    }
    std::printf("PASS: every record delivered; rank 1's reached rank 0 while its chunk ran\n");
  }
  return 0;
}
