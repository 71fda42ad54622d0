#pragma once
// Calls into libraries that choose their own thread counts (CHOLMOD, OpenBLAS), held to
// worker_threads().

#include <type_traits>

namespace khz::reduced::detail {

/// Runs fn(context) with OpenBLAS set to worker_threads() threads and every OpenMP parallel
/// region it reaches, in any library, on the calling thread alone, even one whose num_threads
/// clause asks for more (CHOLMOD 5's 4): an OpenMP teams region of one team with thread_limit 1.
/// CHOLMOD's own OpenMP loops are light memory passes; its work is OpenBLAS's. Given two threads
/// too, their spin-waiting took the cores from OpenBLAS's: a supernodal factorization of a 3-D
/// Laplacian (36³) took 6.3 s instead of 2.1 s on 2 cores. Inside a parallel region (where a
/// teams region may not go, and OpenMP already runs nested regions on one thread) fn just runs.
/// fn must not throw.
void call_thread_limited(void (*fn)(void*), void* context) noexcept;

/// call_thread_limited() for a callable that does not throw (e.g. a lambda calling CHOLMOD).
template <typename Function>
void thread_limited(Function&& function) noexcept {
  static_assert(std::is_nothrow_invocable_v<Function&>, "the limited call must not throw");
  call_thread_limited(
      [](void* context) { (*static_cast<std::remove_reference_t<Function>*>(context))(); },
      &function);
}

}  // namespace khz::reduced::detail
