#pragma once
// Lock-free hand-off of the newest value from one thread to another (the haptic loop's state to
// a render/UI thread, §4.5: the simulation and the haptics run at different rates).

#include <array>
#include <atomic>
#include <cstdint>
#include <type_traits>

namespace khz::haptic {

/// A triple buffer: one writer thread publishes values, one reader thread takes the newest one.
/// Neither ever waits for the other: the writer fills its own slot and swaps it with the middle
/// one; the reader swaps the middle one in when it is newer than what it holds. Values in
/// between are dropped (the reader wants the latest state, not a queue). Every operation is
/// wait-free, allocates nothing and throws nothing as long as T's copy assignment does not.
///
/// Usage (writer): `buffer.back() = state; buffer.publish();`; (reader): `buffer.update();
/// use(buffer.front());`. back() belongs to the writer and front() to the reader; neither may
/// be touched by the other thread.
template <typename T>
class TripleBuffer {
  static_assert(std::is_nothrow_copy_assignable_v<T> || std::is_nothrow_move_assignable_v<T>);

 public:
  TripleBuffer() = default;
  /// All three slots start as `initial`.
  explicit TripleBuffer(const T& initial) : m_slots{initial, initial, initial} {}

  /// Sets every slot to `value` and forgets what was published. Only while no other thread uses
  /// the buffer.
  void reset(const T& value) noexcept {
    m_slots.fill(value);
    m_back = 0;
    m_middle.store(1, std::memory_order_relaxed);
    m_front = 2;
  }

  /// The writer's slot: fill it, then publish().
  T& back() noexcept { return m_slots[m_back]; }
  /// Makes back() the newest value; the writer gets another slot to fill.
  void publish() noexcept {
    const std::uint8_t previous =
        m_middle.exchange(static_cast<std::uint8_t>(m_back | fresh), std::memory_order_acq_rel);
    m_back = previous & index_mask;
  }

  /// Takes the newest published value into front(), if there is one newer than front(); returns
  /// whether there was.
  bool update() noexcept {
    if ((m_middle.load(std::memory_order_relaxed) & fresh) == 0) return false;
    const std::uint8_t previous = m_middle.exchange(m_front, std::memory_order_acq_rel);
    m_front = previous & index_mask;
    return true;
  }
  /// The reader's slot: the newest value as of the last update().
  const T& front() const noexcept { return m_slots[m_front]; }

 private:
  static constexpr std::uint8_t index_mask = 0x3;
  static constexpr std::uint8_t fresh = 0x4;  // the middle slot holds an unread value

  std::array<T, 3> m_slots{};
  std::uint8_t m_back = 0;                // writer only
  std::atomic<std::uint8_t> m_middle{1};  // shared: index | fresh
  std::uint8_t m_front = 2;               // reader only
};

}  // namespace khz::haptic
