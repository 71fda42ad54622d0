#pragma once
// A reduced::WorkGroup whose processes are threads of this process: the collectives of a
// message-passing job, in memory, so that the libraries' shared precomputations are tested
// without MPI (and under the sanitizers).

#include <khz/reduced/work_group.hpp>

#include <barrier>
#include <functional>
#include <memory>
#include <span>
#include <vector>

namespace khz::test {

/// `size` members that run together. Each member is used from its own thread; sums add the
/// members' values in rank order, so results do not depend on which thread comes first. Members
/// that make different collectives at the same time (a sum against a checkpoint, or sums of
/// different lengths), which MPI would answer with a hang or garbage, abort the test program
/// with a message saying so.
class ThreadWorkGroup {
 public:
  explicit ThreadWorkGroup(int size);
  ~ThreadWorkGroup();
  ThreadWorkGroup(const ThreadWorkGroup&) = delete;
  ThreadWorkGroup& operator=(const ThreadWorkGroup&) = delete;

  /// Member `rank` (0 ≤ rank < size), valid while the group lives.
  reduced::WorkGroup& member(int rank);

  /// Runs body(rank, member) on one thread per member and waits for all.
  void run(const std::function<void(int rank, reduced::WorkGroup& member)>& body);

 private:
  class Member;
  friend class Member;

  int m_size;
  std::barrier<> m_barrier;
  std::vector<std::vector<double>> m_values;     // each member's sum() contribution
  std::vector<reduced::GroupStatus> m_statuses;  // each member's checkpoint() contribution
  std::vector<std::size_t> m_calls;  // each member's current collective: sum length, or npos
  std::vector<std::unique_ptr<Member>> m_members;
};

}  // namespace khz::test
