#pragma once
// How many threads Kilohertz's precomputations run at once: one setting for its own OpenMP
// loops and for the threads of its dependencies (issue 23 item 4).

#include <khz/reduced/export.hpp>

namespace khz::reduced {

/// The most threads one precomputation of any Kilohertz library runs at once: its own OpenMP
/// loops (FEM assembly, polynomials, fields, pointshells, trees), CHOLMOD's factorizations and
/// solves (Debian's CHOLMOD 5 asks OpenMP for 4 threads whatever OMP_NUM_THREADS says) and
/// OpenBLAS's BLAS and LAPACK calls (from CHOLMOD, ARPACK and QR factorizations); Eigen's
/// matrix products inside the libraries run on the calling thread. The calling thread counts as
/// one.
///
/// The default (set_worker_threads(0), or never set) is the smaller of the cores the calling
/// thread may run on (its affinity mask: a haptic loop pinned to a core takes that core away,
/// see haptic::LoopOptions::cpu) and OpenMP's own default (OMP_NUM_THREADS if set). The `khz`
/// tools read the environment variable KHZ_THREADS; scenes take a "threads" key.
/// Never below 1. Thread-safe; costs one system call when the default is in effect.
KHZ_REDUCED_API int worker_threads() noexcept;

/// Sets worker_threads() for the whole process, from any thread, for the computations that
/// start afterwards: `count` ≥ 1, or 0 for the default. Does not change OMP_NUM_THREADS or any
/// OpenMP setting of the caller's own loops.
/// @throws Error if count < 0.
KHZ_REDUCED_API void set_worker_threads(int count);

/// Sets worker_threads() from the environment variable `variable` (the khz tools use
/// KHZ_THREADS, the default) when it is set and not empty; does nothing otherwise.
/// @returns the count set, or 0 if the variable was not set.
/// @throws Error naming the variable if its value is not a whole number ≥ 1.
KHZ_REDUCED_API int set_worker_threads_from_environment(const char* variable = "KHZ_THREADS");

/// Sets worker_threads() for its lifetime and restores the previous setting (the value given
/// to set_worker_threads(), 0 for the default) when it ends. For one computation, e.g. a
/// scene's preparation with its "threads" key; not for computations overlapping in time on
/// other threads, which it would limit too.
class KHZ_REDUCED_API ScopedWorkerThreads {
 public:
  /// @throws Error if count < 0.
  explicit ScopedWorkerThreads(int count);
  ~ScopedWorkerThreads();
  ScopedWorkerThreads(const ScopedWorkerThreads&) = delete;
  ScopedWorkerThreads& operator=(const ScopedWorkerThreads&) = delete;

 private:
  int m_previous;
};

}  // namespace khz::reduced
