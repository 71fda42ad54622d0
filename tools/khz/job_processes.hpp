#pragma once
// `mpirun -np N khz prep SCENE`: the processes an MPI launcher started, as one WorkGroup that
// shares the preparation (issue 24, item 4).

#include <khz/reduced/work_group.hpp>

#include <memory>
#include <string_view>

namespace khz::tool {

/// The job this khz process belongs to. Started by mpirun / mpiexec as several processes (the
/// launcher's environment says so), it starts MPI (khz::mpi::Environment) and spans them with a
/// khz::mpi::MpiWorkGroup, and ends MPI when destroyed; started alone, it is a job of one.
class JobProcesses {
 public:
  /// `command` names the khz command in messages.
  /// @throws reduced::Error if started as several processes by a khz built without MPI
  ///         (KHZ_WITH_MPI off), or if MPI cannot start.
  explicit JobProcesses(std::string_view command);
  ~JobProcesses();
  JobProcesses(const JobProcesses&) = delete;
  JobProcesses& operator=(const JobProcesses&) = delete;

  /// The job's processes, or null for a process alone.
  reduced::WorkGroup* group() noexcept;
  /// Whether this process shows progress and the summary: the first of the job.
  bool leads() const noexcept;

 private:
  struct Mpi;
  std::unique_ptr<Mpi> m_mpi;
};

}  // namespace khz::tool
