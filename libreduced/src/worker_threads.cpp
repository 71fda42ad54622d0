#include "detail/thread_limited_call.hpp"

#include <khz/reduced/errors.hpp>
#include <khz/reduced/worker_threads.hpp>

#include <dlfcn.h>
#include <omp.h>
#include <sched.h>

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cstdlib>
#include <cstring>
#include <string>

namespace khz::reduced {
namespace {

/// set_worker_threads()'s value; 0 for the default.
std::atomic<int> configured_threads{0};

int cores_of_calling_thread() noexcept {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof(set), &set) != 0) return 1;
  return std::max(CPU_COUNT(&set), 1);
}

/// Sets OpenBLAS's thread count when it is the BLAS loaded (looked up at run time: another BLAS
/// may stand in for it through Debian's alternatives) and the count changed.
void set_blas_threads(int count) noexcept {
  using SetThreads = void (*)(int);
  static const auto openblas_set_num_threads =
      reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  static std::atomic<int> applied{0};
  if (openblas_set_num_threads != nullptr && applied.exchange(count) != count) {
    openblas_set_num_threads(count);
  }
}

}  // namespace

int worker_threads() noexcept {
  const int configured = configured_threads.load(std::memory_order_relaxed);
  if (configured > 0) return configured;
  return std::max(1, std::min(cores_of_calling_thread(), omp_get_max_threads()));
}

void set_worker_threads(int count) {
  if (count < 0) {
    throw Error("set_worker_threads: the thread count must be ≥ 1, or 0 for the default, got " +
                std::to_string(count));
  }
  configured_threads.store(count, std::memory_order_relaxed);
}

int set_worker_threads_from_environment(const char* variable) {
  const char* value = std::getenv(variable);
  if (value == nullptr || *value == '\0') return 0;
  int count = 0;
  const char* end = value + std::strlen(value);
  const auto [stop, error] = std::from_chars(value, end, count);
  if (error != std::errc() || stop != end || count < 1) {
    throw Error(std::string("the environment variable ") + variable +
                " must be a whole number of threads ≥ 1, got \"" + value + "\"");
  }
  set_worker_threads(count);
  return count;
}

ScopedWorkerThreads::ScopedWorkerThreads(int count)
    : m_previous(configured_threads.load(std::memory_order_relaxed)) {
  set_worker_threads(count);
}

ScopedWorkerThreads::~ScopedWorkerThreads() {
  configured_threads.store(m_previous, std::memory_order_relaxed);
}

namespace detail {

void call_thread_limited(void (*fn)(void*), void* context) noexcept {
  set_blas_threads(worker_threads());
  if (omp_get_level() > 0) {
    fn(context);
    return;
  }
#pragma omp teams num_teams(1) thread_limit(1)
  fn(context);
}

}  // namespace detail
}  // namespace khz::reduced
