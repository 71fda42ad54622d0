#pragma once
// Processes that share one precomputation (e.g. the ranks of an MPI job), as a precomputation
// sees them. libreduced depends on no message-passing library: khz::mpi implements this
// interface over MPI (khz/mpi/mpi_work_group.hpp), and tests can implement it with threads.

#include <khz/reduced/export.hpp>

#include <cstdint>
#include <exception>
#include <span>
#include <string>
#include <string_view>
#include <utility>

namespace khz::reduced {

/// What a process brings to a WorkGroup::checkpoint(), and what the group's checkpoint returns.
struct KHZ_REDUCED_API GroupStatus {
  enum class State {
    running,    ///< Nothing went wrong.
    cancelled,  ///< The process's progress callback asked to stop.
    failed,     ///< The process's share threw; `message` says what.
  };
  State state = State::running;
  /// Brought: what failed or cancelled. Returned: the message of the process the state comes
  /// from (empty while running).
  std::string message;
  /// Brought: units this process finished since its previous checkpoint. Returned: the sum
  /// over the group.
  std::int64_t done = 0;
  /// Returned: the process the state and message come from (-1 while running).
  int rank = -1;
};

/// The processes that share a computation. Every process of the group makes the same
/// collective calls (sum(), checkpoint()) in the same order, as MPI's collectives require;
/// the computations that take a group (ReducedModelOptions::group, …) guarantee that, also when
/// one process fails or cancels: its failure reaches the others at the next checkpoint and
/// every process then throws.
class KHZ_REDUCED_API WorkGroup {
 public:
  virtual ~WorkGroup();

  /// This process's index, 0 ≤ rank() < size().
  virtual int rank() const noexcept = 0;
  /// Processes in the group, ≥ 1.
  virtual int size() const noexcept = 0;
  /// Collective: replaces `values` on every process by their element-wise sum over the group.
  /// Every process passes a span of the same length. @throws Error if the transport fails.
  virtual void sum(std::span<double> values) = 0;
  /// Collective: the group's status. State: failed if any process brings failed, else
  /// cancelled if any brings cancelled, else running; message and rank: those of the
  /// lowest-ranked process in that state; done: the sum of every process's `done`.
  /// @throws Error if the transport fails.
  virtual GroupStatus checkpoint(const GroupStatus& mine) = 0;
};

/// The group's status from every process's (index = rank), by WorkGroup::checkpoint()'s rule:
/// the most severe state (failed, then cancelled, then running), with the message and rank of
/// the lowest-ranked process in it, and the sum of `done`. For implementations of checkpoint()
/// that have every status in one place.
KHZ_REDUCED_API GroupStatus combine_statuses(std::span<const GroupStatus> statuses);

/// Ends a shared computation called `what` as the checkpoint result `group` says, alike on
/// every process: returns while it is running. When a process failed, the process it comes
/// from (`rank` == group.rank) rethrows `own_failure` if it has one; every other throws Error
/// "<what> failed on rank R of N: <message>". When one cancelled, that process throws
/// Cancelled with its own message and every other Cancelled "<what> cancelled on rank R of N".
/// `rank` and `size` are this process's and the group's (0 and 1 for a process alone).
KHZ_REDUCED_API void stop_unless_running(const GroupStatus& group, int rank, int size,
                                         std::string_view what,
                                         const std::exception_ptr& own_failure);

/// The share [begin, end) of `count` equal units that process `rank` of `size` takes:
/// contiguous, in rank order, sizes differing by at most one.
inline std::pair<std::int64_t, std::int64_t> share_of(std::int64_t count, int rank,
                                                      int size) noexcept {
  const auto begin = count * rank / size;
  const auto end = count * (rank + 1) / size;
  return {begin, end};
}

}  // namespace khz::reduced
