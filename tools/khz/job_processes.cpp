#include "job_processes.hpp"

#include <khz/reduced/errors.hpp>

#include <algorithm>
#include <cstdlib>
#include <string>

#ifdef KHZ_TOOL_WITH_MPI
#include <khz/mpi/environment.hpp>
#include <khz/mpi/mpi_work_group.hpp>

#include <unistd.h>

#include <csignal>
#endif

namespace khz::tool {
namespace {

/// The number of processes the MPI launcher started, from its environment (Open MPI's, or the
/// PMI variables of MPICH's Hydra); 1 when no launcher started this one.
int launched_processes() {
  for (const char* variable : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    if (const char* value = std::getenv(variable)) return std::max(1, std::atoi(value));
  }
  return 1;
}

#ifdef KHZ_TOOL_WITH_MPI
/// The launcher ends the job's other processes with SIGTERM when one dies (killed, out of
/// memory): the first process then says why before it goes, so the job's output does not end
/// with the launcher's note alone.
void on_launcher_terminate(int) {
  static const char message[] =
      "khz: stopped by the MPI launcher: another process of the job ended (see the launcher's "
      "message); the product cache keeps only complete products\n";
  [[maybe_unused]] const auto written = ::write(STDERR_FILENO, message, sizeof message - 1);
  ::_exit(128 + SIGTERM);
}
#endif

}  // namespace

#ifdef KHZ_TOOL_WITH_MPI
struct JobProcesses::Mpi {
  Mpi() : environment(argc, argv) {}
  int argc = 0;
  char** argv = nullptr;
  mpi::Environment environment;
  mpi::MpiWorkGroup group;
};
#else
struct JobProcesses::Mpi {};
#endif

JobProcesses::JobProcesses([[maybe_unused]] std::string_view command) {
  const int processes = launched_processes();
  if (processes == 1) return;
#ifdef KHZ_TOOL_WITH_MPI
  m_mpi = std::make_unique<Mpi>();
  if (m_mpi->group.rank() == 0) std::signal(SIGTERM, on_launcher_terminate);
#else
  throw reduced::Error(
      "khz " + std::string(command) + " was started as " + std::to_string(processes) +
      " processes (mpirun), but this khz was built without MPI: configure with "
      "-DKHZ_WITH_MPI=ON (Debian: libopenmpi-dev openmpi-bin), or run one process");
#endif
}

JobProcesses::~JobProcesses() = default;

reduced::WorkGroup* JobProcesses::group() noexcept {
#ifdef KHZ_TOOL_WITH_MPI
  if (m_mpi) return &m_mpi->group;
#endif
  return nullptr;
}

bool JobProcesses::leads() const noexcept {
#ifdef KHZ_TOOL_WITH_MPI
  if (m_mpi) return m_mpi->group.rank() == 0;
#endif
  return true;
}

}  // namespace khz::tool
