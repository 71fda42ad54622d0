#include <khz/test/threads_that_ran.hpp>

#include <dirent.h>
#include <sched.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <utility>

namespace khz::test {
namespace {

/// What a thread has done so far: its context switches (voluntary and involuntary) and its time
/// on a CPU (ns, /proc schedstat). A thread woken for work may still be running when sampled,
/// not yet switched out, so switches alone can miss it; a thread that ran less than a scheduler
/// tick may not show its time yet, so time alone can too.
struct Activity {
  long switches = 0;
  long long cpu_ns = 0;
  bool operator==(const Activity&) const = default;
};

std::map<pid_t, Activity> activity() {
  std::map<pid_t, Activity> threads;
  for (const pid_t thread : process_threads()) {
    const std::string task = "/proc/self/task/" + std::to_string(thread);
    Activity& a = threads[thread];
    std::ifstream status(task + "/status");
    for (std::string line; std::getline(status, line);) {
      if (line.find("ctxt_switches:") != std::string::npos) {
        a.switches += std::strtol(line.c_str() + line.find(':') + 1, nullptr, 10);
      }
    }
    std::ifstream schedstat(task + "/schedstat");
    schedstat >> a.cpu_ns;
  }
  return threads;
}

/// "id (name) state, user + system ticks" from the thread's stat line.
std::string describe(pid_t thread) {
  std::ifstream stat("/proc/self/task/" + std::to_string(thread) + "/stat");
  std::string line;
  std::getline(stat, line);
  const std::size_t name_end = line.rfind(')');
  if (name_end == std::string::npos) return std::to_string(thread) + " (ended)";
  std::istringstream fields(line.substr(name_end + 2));
  std::string field;
  std::vector<std::string> after_name;  // state is field 3 of stat(5), utime 14, stime 15
  while (fields >> field && after_name.size() < 13) after_name.push_back(field);
  if (after_name.size() < 13) return line;
  return line.substr(0, name_end + 1) + " " + after_name[0] + ", " + after_name[11] + " + " +
         after_name[12] + " ticks";
}

}  // namespace

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

std::vector<std::string> other_threads_in_a_second_run(const std::function<void()>& work) {
  work();
  wait_until_other_threads_are_still();
  return other_threads_that_ran(work);
}

void wait_until_other_threads_are_still() {
  constexpr int window_us = 50'000;  // far longer than a sched_yield() loop's turns
  constexpr int max_windows = 100;   // 5 s: then measure anyway, and let the test tell
  const pid_t self = gettid();
  std::map<pid_t, Activity> before = activity();
  before.erase(self);
  for (int window = 0; window < max_windows; ++window) {
    usleep(window_us);
    std::map<pid_t, Activity> after = activity();
    after.erase(self);
    if (after == before) return;
    before = std::move(after);
  }
}

std::vector<std::string> other_threads_that_ran(const std::function<void()>& work) {
  const std::map<pid_t, Activity> before = activity();
  work();
  const std::map<pid_t, Activity> after = activity();
  const pid_t self = gettid();
  std::vector<std::string> ran;
  for (const auto& [thread, done] : after) {
    if (thread == self) continue;
    const auto earlier = before.find(thread);
    if (earlier != before.end() && earlier->second == done) continue;
    ran.push_back(describe(thread));
  }
  return ran;
}

std::string listed(const std::vector<std::string>& threads) {
  std::string text;
  for (const std::string& thread : threads) text += "\n  " + thread;
  return text;
}

int usable_cores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof(set), &set) != 0) return 1;
  return CPU_COUNT(&set);
}

}  // namespace khz::test
