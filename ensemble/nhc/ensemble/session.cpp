// MPI initialisation when started by mpirun, one process otherwise (session.hpp).
#include "nhc/ensemble/session.hpp"

#include <cstdlib>
#include <stdexcept>

#ifdef NHC_HAVE_MPI
#include <mpi.h>
#endif

namespace nhc::ensemble {

bool started_by_mpirun() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (std::getenv(name) != nullptr) return true;
  return false;
}

std::string how_to_get_mpi() {
  return "this nhc was built without MPI: install Debian's OpenMPI (apt-get install libopenmpi-dev openmpi-bin; "
         "scripts/setup.sh does) and configure again (cmake -S . -B build)";
}

Session::Session() {
  if (!started_by_mpirun()) return;
#ifdef NHC_HAVE_MPI
  int initialized = 0;
  MPI_Initialized(&initialized);
  if (!initialized) {
    int provided = 0;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
    if (provided < MPI_THREAD_FUNNELED) {
      MPI_Finalize();
      throw std::runtime_error("the MPI library does not allow threads (MPI_THREAD_FUNNELED)");
    }
  }
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  mpi_ = true;
#else
  throw std::runtime_error("started by mpirun, but " + how_to_get_mpi());
#endif
}

Session::~Session() {
#ifdef NHC_HAVE_MPI
  if (mpi_) MPI_Finalize();
#endif
}

void Session::broadcast(std::vector<char>& bytes) const {
#ifdef NHC_HAVE_MPI
  if (!mpi_) return;
  long size = static_cast<long>(bytes.size());
  MPI_Bcast(&size, 1, MPI_LONG, 0, MPI_COMM_WORLD);
  bytes.resize(static_cast<std::size_t>(size));
  if (size > 0) MPI_Bcast(bytes.data(), static_cast<int>(size), MPI_BYTE, 0, MPI_COMM_WORLD);
#else
  (void)bytes;
#endif
}

int Session::broadcast(int value) const {
#ifdef NHC_HAVE_MPI
  if (mpi_) MPI_Bcast(&value, 1, MPI_INT, 0, MPI_COMM_WORLD);
#endif
  return value;
}

void Session::abort(int code) const {
#ifdef NHC_HAVE_MPI
  if (mpi_ && size_ > 1) MPI_Abort(MPI_COMM_WORLD, code);
#else
  (void)code;
#endif
}

}  // namespace nhc::ensemble
