#pragma once
// What the hardware adapter examples share: five seconds of a soft spring to the workspace
// centre, rendered at the device's nominal rate through the safety layer.

#include <khz/haptic/device/device.hpp>
#include <khz/haptic/device/safe_device.hpp>

#include <chrono>
#include <cstdio>
#include <thread>

namespace khz::example {

/// One haptic cycle: read, a 50 N/m spring to the origin, write.
inline void spring_cycle(haptic::SafeDevice& safe) {
  haptic::DeviceState state;
  safe.read(state);
  haptic::Wrench wrench;
  wrench.force = -50.0 * state.pose.position;
  safe.write(wrench);
}

/// Runs spring_cycle() for five seconds on this thread, with the watchdog armed, and reports the
/// safety statistics. For devices whose SDK leaves the servo loop to the application.
inline int run_spring(haptic::Device& device) {
  haptic::SafeDevice safe(device, {.deadline_tolerance = 2e-4, .ramp_cycles = 200});
  safe.open();
  using clock = std::chrono::steady_clock;
  const auto period = std::chrono::duration<double>(1.0 / device.capabilities().nominal_rate);
  const auto start = clock::now();
  auto next = start;
  const auto seconds = [&](clock::time_point t) {
    return std::chrono::duration<double>(t - start).count();
  };
  while (next - start < std::chrono::seconds(5)) {
    next += std::chrono::duration_cast<clock::duration>(period);
    safe.begin_cycle(seconds(next));
    spring_cycle(safe);
    safe.end_cycle(seconds(clock::now()));
    std::this_thread::sleep_until(next);
  }
  safe.close();
  const haptic::SafetyStatistics& s = safe.statistics();
  std::printf("%s: %llu cycles, %llu clamped, %llu zeroed, %llu deadline misses\n",
              device.capabilities().name.c_str(), static_cast<unsigned long long>(s.writes),
              static_cast<unsigned long long>(s.clamped_writes),
              static_cast<unsigned long long>(s.zeroed_writes),
              static_cast<unsigned long long>(s.deadline_misses));
  return 0;
}

}  // namespace khz::example
