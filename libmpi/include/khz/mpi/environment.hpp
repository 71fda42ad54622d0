#pragma once
// MPI's start and end for programs that use MPI only through Kilohertz.

#include <khz/mpi/export.hpp>

namespace khz::mpi {

/// Initializes MPI on construction (MPI_Init_thread with MPI_THREAD_FUNNELED: only the thread
/// that made the Environment calls MPI; the libraries' worker threads never do) and finalizes
/// it on destruction, unless MPI was already initialized by someone else, who then finalizes
/// it. Create one at the start of main(), before any MpiWorkGroup, so it outlives them.
class KHZ_MPI_API Environment {
 public:
  /// @throws reduced::Error if MPI_Init_thread fails or gives less than MPI_THREAD_FUNNELED.
  Environment(int& argc, char**& argv);
  ~Environment();
  Environment(const Environment&) = delete;
  Environment& operator=(const Environment&) = delete;

  /// MPI_COMM_WORLD's rank and size.
  int rank() const noexcept { return m_rank; }
  int size() const noexcept { return m_size; }

 private:
  bool m_owner = false;
  int m_rank = 0;
  int m_size = 1;
};

}  // namespace khz::mpi
