#pragma once
// Replaces the global operator new to record the largest single request and count requests, so a
// test can prove that a hostile size field in a file is rejected before anything sized by it is
// allocated, or that a hot path (a time step, a force evaluation) allocates nothing.
// Include in exactly one source file of a test program (it defines operator new and delete).

#include <khz/test/sanitizers.hpp>

#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <new>

namespace khz::test {
/// Largest single request to operator new since it was last set to 0.
inline std::atomic<std::size_t> largest_allocation{0};
/// Number of heap allocations since it was last set to 0: calls to operator new and, where
/// allocation_count_sees_malloc, to malloc, calloc and realloc (Eigen allocates with malloc).
inline std::atomic<std::size_t> allocation_count{0};
}  // namespace khz::test

// Counting malloc means replacing it, which AddressSanitizer does itself: sanitized builds count
// operator new only.
#if defined(KHZ_TEST_ADDRESS_SANITIZER)
namespace khz::test {
inline constexpr bool allocation_count_sees_malloc = false;
}
#else
namespace khz::test {
inline constexpr bool allocation_count_sees_malloc = true;
}
extern "C" {
void* __libc_malloc(std::size_t size);
void* __libc_calloc(std::size_t count, std::size_t size);
void* __libc_realloc(void* memory, std::size_t size);
void* malloc(std::size_t size) {
  ++khz::test::allocation_count;
  return __libc_malloc(size);
}
void* calloc(std::size_t count, std::size_t size) {
  ++khz::test::allocation_count;
  return __libc_calloc(count, size);
}
void* realloc(void* memory, std::size_t size) {
  ++khz::test::allocation_count;
  return __libc_realloc(memory, size);
}
}
#endif

// This replacement pairs malloc with free; GCC cannot see that the delete below only ever
// receives pointers from this new, and warns at -O1 and above.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t size) {
  if constexpr (!khz::test::allocation_count_sees_malloc) ++khz::test::allocation_count;
  std::size_t seen = khz::test::largest_allocation.load();
  while (size > seen && !khz::test::largest_allocation.compare_exchange_weak(seen, size)) {
  }
  if (void* memory = std::malloc(size == 0 ? 1 : size)) return memory;
  throw std::bad_alloc();
}
void operator delete(void* memory) noexcept { std::free(memory); }
void operator delete(void* memory, std::size_t) noexcept { std::free(memory); }
#pragma GCC diagnostic pop
