#pragma once
// Replaces the global operator new to record the largest single request, so a test can prove
// that a hostile size field in a file is rejected before anything sized by it is allocated.
// Include in exactly one source file of a test program (it defines operator new and delete).

#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <new>

namespace khz::test {
/// Largest single request to operator new since it was last set to 0.
inline std::atomic<std::size_t> largest_allocation{0};
}  // namespace khz::test

// This replacement pairs malloc with free; GCC cannot see that the delete below only ever
// receives pointers from this new, and warns at -O1 and above.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t size) {
  std::size_t seen = khz::test::largest_allocation.load();
  while (size > seen && !khz::test::largest_allocation.compare_exchange_weak(seen, size)) {
  }
  if (void* memory = std::malloc(size == 0 ? 1 : size)) return memory;
  throw std::bad_alloc();
}
void operator delete(void* memory) noexcept { std::free(memory); }
void operator delete(void* memory, std::size_t) noexcept { std::free(memory); }
#pragma GCC diagnostic pop
