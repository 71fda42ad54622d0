#pragma once
// Lock-free commands into the haptic loop (a UI thread asks, the loop applies them between
// cycles).

#include <array>
#include <atomic>
#include <cstddef>
#include <type_traits>

namespace khz::haptic {

/// A bounded single-producer, single-consumer queue of trivially copyable commands: one thread
/// push()es, one thread pop()s; both are wait-free, allocate nothing and throw nothing. A full
/// queue refuses the push (returns false) rather than block the sender or the loop.
template <typename T, std::size_t Capacity>
class CommandQueue {
  static_assert(std::is_trivially_copyable_v<T>, "commands are copied between threads");
  static_assert(Capacity >= 1);

 public:
  /// Enqueues `command`; false if the queue holds Capacity commands already. Producer only.
  bool push(const T& command) noexcept {
    const std::size_t tail = m_tail.load(std::memory_order_relaxed);
    const std::size_t next = advance(tail);
    if (next == m_head.load(std::memory_order_acquire)) return false;
    m_items[tail] = command;
    m_tail.store(next, std::memory_order_release);
    return true;
  }
  /// Dequeues the oldest command into `command`; false if there is none. Consumer only.
  bool pop(T& command) noexcept {
    const std::size_t head = m_head.load(std::memory_order_relaxed);
    if (head == m_tail.load(std::memory_order_acquire)) return false;
    command = m_items[head];
    m_head.store(advance(head), std::memory_order_release);
    return true;
  }

 private:
  static constexpr std::size_t slots = Capacity + 1;  // one slot tells full from empty
  static constexpr std::size_t advance(std::size_t i) noexcept {
    return i + 1 == slots ? 0 : i + 1;
  }

  std::array<T, slots> m_items{};
  alignas(64) std::atomic<std::size_t> m_head{0};  // consumer
  alignas(64) std::atomic<std::size_t> m_tail{0};  // producer
};

}  // namespace khz::haptic
