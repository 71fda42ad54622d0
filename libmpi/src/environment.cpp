#include <khz/mpi/environment.hpp>

#include "mpi_error.hpp"

namespace khz::mpi {

Environment::Environment(int& argc, char**& argv) {
  int initialized = 0;
  detail::check(MPI_Initialized(&initialized), "MPI_Initialized");
  if (!initialized) {
    int provided = MPI_THREAD_SINGLE;
    detail::check(MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
    m_owner = true;
    if (provided < MPI_THREAD_FUNNELED) {
      MPI_Finalize();
      throw reduced::Error("MPI_Init_thread: this MPI does not provide MPI_THREAD_FUNNELED");
    }
  }
  detail::check(MPI_Comm_rank(MPI_COMM_WORLD, &m_rank), "MPI_Comm_rank");
  detail::check(MPI_Comm_size(MPI_COMM_WORLD, &m_size), "MPI_Comm_size");
}

Environment::~Environment() {
  if (m_owner) MPI_Finalize();
}

}  // namespace khz::mpi
