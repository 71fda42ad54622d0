#include "other_threads_off_cpu.hpp"

#include <dirent.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace khz::haptic::detail {

std::vector<pid_t> process_threads() {
  std::vector<pid_t> threads;
  DIR* tasks = opendir("/proc/self/task");
  if (tasks == nullptr) return threads;
  while (const dirent* entry = readdir(tasks)) {
    if (entry->d_name[0] != '.') threads.push_back(static_cast<pid_t>(std::atoi(entry->d_name)));
  }
  closedir(tasks);
  return threads;
}

OtherThreadsOffCpu::OtherThreadsOffCpu(int cpu) : m_cpu(cpu), m_listed(process_threads()) {
  std::sort(m_listed.begin(), m_listed.end());
  const pid_t self = gettid();
  for (const pid_t thread : m_listed) {
    if (thread == self) continue;
    cpu_set_t mask;
    CPU_ZERO(&mask);
    // A thread that ended since the listing has nothing to move.
    if (sched_getaffinity(thread, sizeof(mask), &mask) != 0) continue;
    if (!CPU_ISSET(cpu, &mask) || CPU_COUNT(&mask) == 1) continue;
    CPU_CLR(cpu, &mask);
    if (sched_setaffinity(thread, sizeof(mask), &mask) != 0) {
      if (errno != ESRCH) {
        m_failures.push_back("thread " + std::to_string(thread) + ": " + std::strerror(errno));
      }
      continue;
    }
    m_moved.push_back(thread);  // in order, as m_listed
    const bool known = std::any_of(m_masks_made.begin(), m_masks_made.end(),
                                   [&](const cpu_set_t& made) { return CPU_EQUAL(&made, &mask); });
    if (!known) m_masks_made.push_back(mask);
  }
}

OtherThreadsOffCpu::~OtherThreadsOffCpu() {
  for (const pid_t thread : process_threads()) {
    const bool moved = std::binary_search(m_moved.begin(), m_moved.end(), thread);
    const bool started_since = !std::binary_search(m_listed.begin(), m_listed.end(), thread);
    if (!moved && !started_since) continue;
    cpu_set_t mask;
    CPU_ZERO(&mask);
    if (sched_getaffinity(thread, sizeof(mask), &mask) != 0) continue;
    const bool made_here =
        std::any_of(m_masks_made.begin(), m_masks_made.end(),
                    [&](const cpu_set_t& made) { return CPU_EQUAL(&made, &mask); });
    if (!made_here) continue;
    CPU_SET(m_cpu, &mask);
    sched_setaffinity(thread, sizeof(mask), &mask);  // a thread that just ended needs nothing
  }
}

}  // namespace khz::haptic::detail
