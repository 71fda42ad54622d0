#include "job_processes.hpp"

#include <khz/reduced/errors.hpp>

#include <algorithm>
#include <cstdlib>
#include <string>

#ifdef KHZ_TOOL_WITH_MPI
#include <khz/mpi/environment.hpp>
#include <khz/mpi/mpi_work_group.hpp>
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
