// Your own device in the haptic cycle (docs/DEVICES.md): a Device subclass standing in for a
// vendor SDK — here a tool point that a script moves down through the plane z = 0 — behind the
// SafeDevice every device goes through, and a cycle that renders a virtual wall (1000 N/m) with
// the watchdog armed. Prints what the device was sent. Installed headers only (Kilohertz::haptic).
#include <khz/haptic/device/device.hpp>
#include <khz/haptic/device/safe_device.hpp>

#include <cstdio>

namespace kh = khz::haptic;

/// A 3-DOF device whose tool point descends 1 mm per read from z = 5 mm (stand-in for an SDK's
/// position query), and which remembers the last force it was sent (stand-in for its force
/// command). Device axes, SI units.
class ScriptedDevice final : public kh::Device {
 public:
  ScriptedDevice() {
    m_capabilities.name = "scripted";
    m_capabilities.input_dof = 3;
    m_capabilities.output_dof = 3;
    m_capabilities.max_force = 3.0;         // N
    m_capabilities.max_stiffness = 2000.0;  // N/m
  }
  void open() override { m_open = true; }             // an SDK's connect; may throw Error / IoError
  void close() noexcept override { m_open = false; }  // zero output, disconnect
  bool is_open() const noexcept override { return m_open; }
  const kh::DeviceCapabilities& capabilities() const noexcept override { return m_capabilities; }
  bool read(kh::DeviceState& state) noexcept override {  // once per haptic cycle
    state = kh::DeviceState{};
    state.pose.position.z() = 0.005 - 0.001 * static_cast<double>(m_reads);
    state.time = 1e-3 * static_cast<double>(m_reads++);
    state.valid = true;
    return true;
  }
  bool write(const kh::Wrench& wrench) noexcept override {  // the SDK's force command
    sent = wrench.force;
    return true;
  }
  Eigen::Vector3d sent = Eigen::Vector3d::Zero();

 private:
  kh::DeviceCapabilities m_capabilities;
  bool m_open = false;
  long m_reads = 0;
};

int main() {
  ScriptedDevice device;
  kh::SafeDevice safe(device);  // identity mapping; limits from the device's capabilities
  safe.open();
  for (int cycle = 0; cycle < 10; ++cycle) {
    const double now = 1e-3 * cycle, deadline = now + 1e-3;  // the loop's clock (s)
    safe.begin_cycle(deadline);                              // optional: arms the watchdog
    kh::DeviceState s;
    safe.read(s);  // virtual-world pose; false → s.valid false, last good pose
    kh::Wrench w;  // anything, even NaN; here a wall at z = 0, 1000 N/m
    w.force.z() = s.pose.position.z() < 0.0 ? -1000.0 * s.pose.position.z() : 0.0;
    safe.write(w);               // mapped, checked, clamped, sent
    safe.end_cycle(now + 1e-4);  // late → the next write slews from what the device held
    std::printf("z = %5.1f mm: wall %4.1f N, device sent %4.1f N\n", 1e3 * s.pose.position.z(),
                w.force.z(), device.sent.z());
  }
  safe.close();
}
