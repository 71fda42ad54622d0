#pragma once
// The processes of an MPI communicator as a reduced::WorkGroup: what lets ReducedModel's
// precompute (and the other shared precomputations) split its work over the ranks of an MPI job.

#include <khz/mpi/export.hpp>
#include <khz/reduced/work_group.hpp>

#include <mpi.h>

#include <span>

namespace khz::mpi {

/// The ranks of an MPI communicator, for ReducedModelOptions::group and the like.
///
/// Collectives run on a private duplicate of the communicator, so they never match the
/// application's own messages, and report errors instead of aborting the job (MPI's default):
/// a failed call throws reduced::Error with MPI's message. A rank that dies still ends the
/// whole job, as mpirun does for any MPI program.
///
/// Construct and use it on every rank of `communicator` alike (it is collective), from the
/// thread that initialized MPI; destroy it before MPI_Finalize (khz::mpi::Environment does both
/// in the right order when it outlives the group).
class KHZ_MPI_API MpiWorkGroup final : public reduced::WorkGroup {
 public:
  /// Collective over `communicator`.
  /// @throws reduced::Error if MPI is not initialized (MPI_Init, or khz::mpi::Environment) or
  ///         the communicator cannot be duplicated.
  explicit MpiWorkGroup(MPI_Comm communicator = MPI_COMM_WORLD);
  ~MpiWorkGroup() override;
  MpiWorkGroup(const MpiWorkGroup&) = delete;
  MpiWorkGroup& operator=(const MpiWorkGroup&) = delete;

  int rank() const noexcept override { return m_rank; }
  int size() const noexcept override { return m_size; }
  /// MPI_Allreduce (MPI_SUM) in place, in pieces of at most 2²⁸ doubles.
  void sum(std::span<double> values) override;
  /// One MPI_Allgather of every rank's state and count, plus a broadcast of the message when a
  /// rank failed or cancelled.
  reduced::GroupStatus checkpoint(const reduced::GroupStatus& mine) override;

  /// The private communicator the collectives run on.
  MPI_Comm communicator() const noexcept { return m_communicator; }

 private:
  MPI_Comm m_communicator = MPI_COMM_NULL;
  int m_rank = 0;
  int m_size = 1;
};

}  // namespace khz::mpi
