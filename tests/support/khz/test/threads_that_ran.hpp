#pragma once
// Which of the process's threads ran while some work did, counted from outside through
// /proc/self/task: how worker_threads() is checked (issue 23 item 4).

#include <sys/types.h>

#include <functional>
#include <string>
#include <vector>

namespace khz::test {

/// The threads besides the caller that ran while `work` did: those that appeared, and those
/// whose context-switch count or time on a CPU moved (a pool thread woken for work sleeps again
/// after it, or is still running). Each as "id (name) state, user + system ticks", for a failure
/// message.
std::vector<std::string> other_threads_that_ran(const std::function<void()>& work);

/// other_threads_that_ran() on the second of two runs of `work`: a change of thread setting
/// wakes a pool thread or two once, to resize its team, without work. Between the two it waits
/// until the other threads are still (wait_until_other_threads_are_still()).
std::vector<std::string> other_threads_in_a_second_run(const std::function<void()>& work);

/// Returns once no other thread of the process has switched context or run for 50 ms (at most
/// 5 s). An idle pool thread can keep running after the work that woke it, or after it was
/// created: OpenBLAS's server threads (Debian's 0.3.21) call sched_yield() in a loop for a while
/// before they sleep, from the library's start; on an AMD EPYC VM that loop was still running
/// when a test's measured run began in 10 of 30 runs.
void wait_until_other_threads_are_still();

/// The ids of this process's threads (/proc/self/task); empty if it cannot be read.
std::vector<pid_t> process_threads();

/// The lines of other_threads_that_ran(), one per line, for a failure message.
std::string listed(const std::vector<std::string>& threads);

/// How many CPUs the calling thread may run on (its affinity mask).
int usable_cores();

}  // namespace khz::test
