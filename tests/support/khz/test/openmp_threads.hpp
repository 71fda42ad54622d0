#pragma once
// Choosing the OpenMP thread count of the libraries under test. They link OpenMP privately and
// the test programs do not, so the runtime's functions are looked up in the loaded process.

#include <dlfcn.h>

namespace khz::test {

/// Sets the thread count of the OpenMP parallel regions the calling thread starts from now on
/// (omp_set_num_threads). Returns false if no OpenMP runtime is loaded.
inline bool set_openmp_threads(int count) {
  using Setter = void (*)(int);
  const auto setter = reinterpret_cast<Setter>(dlsym(RTLD_DEFAULT, "omp_set_num_threads"));
  if (setter == nullptr) return false;
  setter(count);
  return true;
}

/// The thread count parallel regions use by default (omp_get_max_threads), or 0 if no OpenMP
/// runtime is loaded; to restore it after set_openmp_threads().
inline int openmp_max_threads() {
  using Getter = int (*)();
  const auto getter = reinterpret_cast<Getter>(dlsym(RTLD_DEFAULT, "omp_get_max_threads"));
  return getter == nullptr ? 0 : getter();
}

}  // namespace khz::test
