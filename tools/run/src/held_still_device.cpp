#include <khz/run/held_still_device.hpp>

#include <khz/reduced/errors.hpp>
#include <khz/scene/make_device.hpp>
#include <khz/scene/scene_runtime.hpp>

#include <algorithm>

namespace khz::run {

HeldStillDevice::HeldStillDevice(std::unique_ptr<haptic::Device> device, double hold_time)
    : m_device(std::move(device)), m_hold_time(hold_time) {}

void HeldStillDevice::open() {
  m_device->open();
  m_held = false;
}

bool HeldStillDevice::read(haptic::DeviceState& state) noexcept {
  if (!m_device->read(state)) return false;
  if (!m_held && state.time >= m_hold_time) {
    m_pose = state.pose;
    m_buttons = state.buttons;
    m_held = true;
  }
  if (m_held) {
    state.pose = m_pose;
    state.buttons = m_buttons;
    state.linear_velocity.setZero();
    state.angular_velocity.setZero();
  }
  return true;
}

SteadyPress steady_press(const scene::PreparedScene& prepared,
                         const std::vector<scene::CycleRow>& run, double seconds) {
  const auto strongest = std::max_element(run.begin(), run.end(),
                                          [](const scene::CycleRow& a, const scene::CycleRow& b) {
                                            return a.force.norm() < b.force.norm();
                                          });
  if (strongest == run.end() || !(strongest->force.norm() > 0.0)) {
    throw reduced::Error("steady_press: the run given has no contact to press on");
  }
  SteadyPress press;
  press.hold_time = strongest->time;
  std::vector<std::unique_ptr<haptic::Device>> held;
  std::vector<haptic::Device*> devices;
  for (const scene::HapticDescription& hand : prepared.description.haptic) {
    held.push_back(
        std::make_unique<HeldStillDevice>(scene::make_device(hand.device), press.hold_time));
    devices.push_back(held.back().get());
  }
  scene::SceneRuntime still(prepared, devices);
  scene::RunOptions options;
  options.duration = press.hold_time + seconds;
  press.rows = scene::run_scene(still, options);
  for (int h = 0; h < still.hand_count(); ++h) press.metrics.push_back(still.world().metrics(h));
  return press;
}

}  // namespace khz::run
