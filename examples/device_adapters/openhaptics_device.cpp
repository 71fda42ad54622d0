// A Kilohertz device backed by 3D Systems OpenHaptics (HD API): Phantom Premium, Touch, Omni.
// Built only when the SDK is found (examples/CMakeLists.txt); see docs/DEVICES.md.
//
// OpenHaptics runs its own servo thread. A haptic frame must be bracketed by hdBeginFrame() and
// hdEndFrame() inside a scheduler callback: read() begins the frame, write() ends it, so the
// haptic loop runs its cycle in an hdScheduleAsynchronous() callback (see main()).

#include <khz/haptic/device/device.hpp>
#include <khz/haptic/device/safe_device.hpp>

#include <HD/hd.h>

#include <chrono>
#include <cstdio>

namespace {

using namespace khz::haptic;

class OpenHapticsDevice final : public Device {
 public:
  /// The HD API reports no torque limit: pass the data sheet's (N·m).
  explicit OpenHapticsDevice(double max_torque) { m_capabilities.max_torque = max_torque; }
  ~OpenHapticsDevice() override { close(); }

  void open() override {
    m_handle = hdInitDevice(HD_DEFAULT_DEVICE);
    if (HD_DEVICE_ERROR(hdGetError())) throw IoError("OpenHaptics: no device (hdInitDevice)");
    HDint input = 0, output = 0;
    HDdouble force = 0.0, stiffness = 0.0, box[6] = {};
    hdGetIntegerv(HD_INPUT_DOF, &input);
    hdGetIntegerv(HD_OUTPUT_DOF, &output);
    hdGetDoublev(HD_NOMINAL_MAX_CONTINUOUS_FORCE, &force);  // N
    hdGetDoublev(HD_NOMINAL_MAX_STIFFNESS, &stiffness);     // N/mm
    hdGetDoublev(HD_USABLE_WORKSPACE_DIMENSIONS, box);      // mm: min x y z, max x y z
    m_capabilities.name = "OpenHaptics";
    m_capabilities.input_dof = input >= 6 ? 6 : 3;
    m_capabilities.output_dof = output >= 6 ? 6 : 3;
    m_capabilities.max_force = force;
    m_capabilities.max_stiffness = 1000.0 * stiffness;
    m_capabilities.workspace_min = 1e-3 * Eigen::Vector3d(box[0], box[1], box[2]);
    m_capabilities.workspace_max = 1e-3 * Eigen::Vector3d(box[3], box[4], box[5]);
    hdEnable(HD_FORCE_OUTPUT);
    hdStartScheduler();
    if (HD_DEVICE_ERROR(hdGetError())) {
      hdDisableDevice(m_handle);
      throw IoError("OpenHaptics: the servo loop did not start");
    }
    m_start = std::chrono::steady_clock::now();
    m_open = true;
  }

  void close() noexcept override {
    if (!m_open) return;
    hdDisable(HD_FORCE_OUTPUT);
    hdStopScheduler();
    hdDisableDevice(m_handle);
    m_open = false;
  }

  bool is_open() const noexcept override { return m_open; }
  const DeviceCapabilities& capabilities() const noexcept override { return m_capabilities; }

  bool read(DeviceState& state) noexcept override {
    hdBeginFrame(m_handle);
    m_in_frame = true;
    HDdouble transform[16], velocity[3];  // column-major 4×4 and mm/s
    HDint buttons = 0;
    hdGetDoublev(HD_CURRENT_TRANSFORM, transform);
    hdGetDoublev(HD_CURRENT_VELOCITY, velocity);
    hdGetIntegerv(HD_CURRENT_BUTTONS, &buttons);
    const Eigen::Map<const Eigen::Matrix4d> m(transform);
    state.pose.position = 1e-3 * m.block<3, 1>(0, 3);
    state.pose.orientation = Eigen::Quaterniond(Eigen::Matrix3d(m.block<3, 3>(0, 0)));
    state.linear_velocity = 1e-3 * Eigen::Vector3d(velocity[0], velocity[1], velocity[2]);
    state.has_linear_velocity = true;
    state.buttons = static_cast<std::uint32_t>(buttons);
    state.time = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
    state.valid = !HD_DEVICE_ERROR(hdGetError());
    return state.valid;
  }

  bool write(const Wrench& wrench) noexcept override {
    if (!m_in_frame) return true;  // outside the servo thread (e.g. SafeDevice::close())
    const HDdouble force[3] = {wrench.force.x(), wrench.force.y(), wrench.force.z()};
    const HDdouble torque[3] = {1e3 * wrench.torque.x(), 1e3 * wrench.torque.y(),
                                1e3 * wrench.torque.z()};  // the HD API takes mN·m
    hdSetDoublev(HD_CURRENT_FORCE, force);
    if (m_capabilities.output_dof == 6) hdSetDoublev(HD_CURRENT_TORQUE, torque);
    hdEndFrame(m_handle);
    m_in_frame = false;
    return !HD_DEVICE_ERROR(hdGetError());
  }

 private:
  DeviceCapabilities m_capabilities;
  HHD m_handle = HD_INVALID_HANDLE;
  bool m_open = false;
  bool m_in_frame = false;
  std::chrono::steady_clock::time_point m_start;
};

struct Loop {
  SafeDevice* safe = nullptr;
  int cycles = 0;
};

/// One haptic cycle in the servo thread: a 50 N/m spring to the workspace centre, five seconds.
HDCallbackCode HDCALLBACK haptic_cycle(void* data) {
  Loop& loop = *static_cast<Loop*>(data);
  DeviceState state;
  loop.safe->read(state);
  Wrench wrench;
  wrench.force = -50.0 * state.pose.position;
  loop.safe->write(wrench);
  return ++loop.cycles < 5000 ? HD_CALLBACK_CONTINUE : HD_CALLBACK_DONE;
}

}  // namespace

int main() {
  OpenHapticsDevice device(0.1);
  SafeDevice safe(device, {.ramp_cycles = 200});
  safe.open();
  Loop loop{&safe};
  const HDSchedulerHandle callback =
      hdScheduleAsynchronous(haptic_cycle, &loop, HD_MAX_SCHEDULER_PRIORITY);
  hdWaitForCompletion(callback, HD_WAIT_INFINITE);
  safe.close();
  std::printf("%d cycles, %llu clamped, %llu zeroed\n", loop.cycles,
              static_cast<unsigned long long>(safe.statistics().clamped_writes),
              static_cast<unsigned long long>(safe.statistics().zeroed_writes));
}
