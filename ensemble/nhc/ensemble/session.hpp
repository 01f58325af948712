#pragma once
/// \file session.hpp
/// \brief Where an ensemble runs: the ranks of an MPI job started by mpirun, or one process
/// (its cores as threads). MPI is initialised only when the process was started by a process
/// manager (mpirun, srun), so the same command runs without one.

#include <string>
#include <vector>

namespace nhc::ensemble {

class Session {
 public:
  /// Initialises MPI (MPI_THREAD_FUNNELED: only the main thread communicates) when started by
  /// mpirun; throws std::runtime_error when this nhc was built without MPI but is under mpirun.
  Session();
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  bool uses_mpi() const noexcept { return mpi_; }
  int rank() const noexcept { return rank_; }
  int size() const noexcept { return size_; }
  bool is_root() const noexcept { return rank_ == 0; }

  /// Root's `bytes` on every rank (no-op without MPI).
  void broadcast(std::vector<char>& bytes) const;
  /// Root's value on every rank.
  int broadcast(int value) const;
  /// Ends every rank of an MPI job of more than one rank with `code` (MPI_Abort); else nothing.
  void abort(int code) const;

 private:
  bool mpi_ = false;
  int rank_ = 0;
  int size_ = 1;
};

/// Whether the environment shows a process manager (OMPI_COMM_WORLD_SIZE, PMIX_RANK, PMI_RANK).
bool started_by_mpirun();

/// How to get MPI when it is missing (Debian packages, reconfigure).
std::string how_to_get_mpi();

}  // namespace nhc::ensemble
