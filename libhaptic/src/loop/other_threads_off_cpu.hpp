#pragma once
// Keeping a pinned haptic loop's CPU to itself: the process's other threads are moved off it.

#include <sched.h>
#include <sys/types.h>

#include <string>
#include <vector>

namespace khz::haptic::detail {

/// While it lives, every other thread of the process is kept off one CPU: the threads running
/// when it is made lose that CPU from their affinity masks (unless it is all they have), and
/// threads they start later inherit the smaller mask, so worker pools (OpenMP's, OpenBLAS's, a
/// precomputation's) never run on the haptic loop's core. When it ends, the threads it moved and
/// those started since whose mask is one it made get the CPU back; a thread that was already off
/// the CPU (another pinned loop) keeps its mask. Made on the thread that keeps the CPU; not in
/// the cycle (it reads /proc/self/task and allocates).
class OtherThreadsOffCpu {
 public:
  explicit OtherThreadsOffCpu(int cpu);
  ~OtherThreadsOffCpu();
  OtherThreadsOffCpu(const OtherThreadsOffCpu&) = delete;
  OtherThreadsOffCpu& operator=(const OtherThreadsOffCpu&) = delete;

  /// Threads that could not be moved, as "thread T: reason", for the loop's warnings.
  const std::vector<std::string>& failures() const noexcept { return m_failures; }

 private:
  int m_cpu;
  std::vector<pid_t> m_listed;          // the process's threads when made, sorted
  std::vector<pid_t> m_moved;           // those it took the CPU from, sorted
  std::vector<cpu_set_t> m_masks_made;  // the masks it gave them, without m_cpu
  std::vector<std::string> m_failures;
};

/// The ids of the calling process's threads (/proc/self/task); empty if it cannot be read.
std::vector<pid_t> process_threads();

}  // namespace khz::haptic::detail
