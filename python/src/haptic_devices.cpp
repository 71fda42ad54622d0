// kilohertz.haptic: device capabilities and readings, the Device base class a Python class can
// derive from to run in the haptic cycle, and the recorded-trajectory and simulated-operator
// devices.

#include "haptic_devices.hpp"

#include <khz/haptic/device/simulated_operator.hpp>
#include <khz/haptic/device/trajectory_device.hpp>
#include <khz/haptic/device/trajectory_file.hpp>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <string>
#include <utility>
#include <vector>

#include "arrays.hpp"
#include "bindings.hpp"

namespace khz::python {

PythonDevice::PythonDevice(const haptic::DeviceCapabilities& capabilities)
    : m_capabilities(capabilities) {
  m_capabilities.validate();
}

void PythonDevice::open() {
  const py::gil_scoped_acquire gil;
  if (const py::function open = py::get_override(this, "open")) open();
  m_open = true;
}

void PythonDevice::close() noexcept {
  const py::gil_scoped_acquire gil;
  try {
    if (const py::function close = py::get_override(this, "close")) close();
  } catch (py::error_already_set& error) {
    keep_error(error);
  }
  m_open = false;
}

bool PythonDevice::read(haptic::DeviceState& state) noexcept {
  const py::gil_scoped_acquire gil;
  state.valid = false;
  try {
    const py::function read = py::get_override(this, "read");
    if (!read) {
      PyErr_SetString(PyExc_NotImplementedError,
                      "a kilohertz.haptic.Device subclass must define read()");
      throw py::error_already_set();
    }
    const py::object reading = read();
    if (reading.is_none()) return false;
    state = reading.cast<haptic::DeviceState>();
    state.valid = true;
    return true;
  } catch (py::error_already_set& error) {
    keep_error(error);
  } catch (const py::cast_error&) {
    PyErr_SetString(PyExc_TypeError,
                    "kilohertz.haptic.Device.read() must return a DeviceState or None");
    py::error_already_set error;
    keep_error(error);
  }
  return false;
}

bool PythonDevice::write(const haptic::Wrench& wrench) noexcept {
  const py::gil_scoped_acquire gil;
  try {
    const py::function write = py::get_override(this, "write");
    if (!write) return true;  // an input-only device renders nothing
    const py::object taken = write(py::array_t<double>(3, wrench.force.data()),
                                   py::array_t<double>(3, wrench.torque.data()));
    return taken.is_none() || taken.cast<bool>();
  } catch (py::error_already_set& error) {
    keep_error(error);
  } catch (const py::cast_error&) {
    PyErr_SetString(PyExc_TypeError, "kilohertz.haptic.Device.write() must return a bool or None");
    py::error_already_set error;
    keep_error(error);
  }
  return false;
}

void PythonDevice::keep_error(py::error_already_set& error) noexcept {
  if (!m_error) m_error.emplace(std::move(error));
  m_failed.store(true, std::memory_order_relaxed);
}

void PythonDevice::raise_error() {
  if (!m_error) return;
  py::error_already_set error = std::move(*m_error);
  m_error.reset();
  m_failed.store(false, std::memory_order_relaxed);
  throw error;
}

namespace {

using haptic::DeviceCapabilities;
using haptic::DeviceState;

void bind_capabilities(py::module_& module) {
  py::class_<DeviceCapabilities>(module, "DeviceCapabilities", R"(What a device can sense and
display, in its own axes and SI units (khz::haptic::DeviceCapabilities).)")
      .def(py::init([](std::string name, int input_dof, int output_dof, double max_force,
                       double max_torque, double max_stiffness, const py::handle& workspace_min,
                       const py::handle& workspace_max, double workspace_radius,
                       double nominal_rate) {
             DeviceCapabilities c;
             c.name = std::move(name);
             c.input_dof = input_dof;
             c.output_dof = output_dof;
             c.max_force = max_force;
             c.max_torque = max_torque;
             c.max_stiffness = max_stiffness;
             c.workspace_min = vector3_in(workspace_min, "workspace_min");
             c.workspace_max = vector3_in(workspace_max, "workspace_max");
             c.workspace_radius = workspace_radius;
             c.nominal_rate = nominal_rate;
             c.validate();
             return c;
           }),
           py::kw_only(), py::arg("name") = "device", py::arg("input_dof") = 6,
           py::arg("output_dof") = 6, py::arg("max_force"), py::arg("max_torque") = 0.0,
           py::arg("max_stiffness"), py::arg("workspace_min") = std::vector<double>(3, -0.1),
           py::arg("workspace_max") = std::vector<double>(3, 0.1),
           py::arg("workspace_radius") = std::numeric_limits<double>::infinity(),
           py::arg("nominal_rate") = 1000.0,
           R"(input_dof: 3 or 6; output_dof: 0, 3 or 6; max_force (N) > 0; max_torque (N·m) > 0
when output_dof is 6; max_stiffness (N/m) > 0, the stiffest spring it renders stably;
workspace_min/max: the reachable box (m); workspace_radius: reach from its centre (m);
nominal_rate: servo rate (Hz). Raises kilohertz.Error naming the first invalid value.)")
      .def_readonly("name", &DeviceCapabilities::name)
      .def_readonly("input_dof", &DeviceCapabilities::input_dof)
      .def_readonly("output_dof", &DeviceCapabilities::output_dof)
      .def_readonly("max_force", &DeviceCapabilities::max_force, "N.")
      .def_readonly("max_torque", &DeviceCapabilities::max_torque, "N·m.")
      .def_readonly("max_stiffness", &DeviceCapabilities::max_stiffness, "N/m.")
      .def_property_readonly(
          "workspace_min", [](const DeviceCapabilities& c) { return vector_out(c.workspace_min); })
      .def_property_readonly(
          "workspace_max", [](const DeviceCapabilities& c) { return vector_out(c.workspace_max); })
      .def_readonly("workspace_radius", &DeviceCapabilities::workspace_radius, "m.")
      .def_readonly("nominal_rate", &DeviceCapabilities::nominal_rate, "Hz.");
}

void bind_state(py::module_& module) {
  py::class_<DeviceState>(module, "DeviceState", R"(One reading of a device, in its axes
(khz::haptic::DeviceState): position (3,) m, orientation (4,) unit quaternion (w, x, y, z),
optional linear_velocity (m/s) and angular_velocity (rad/s) (None when not sensed), buttons
(bit i: button i held), time (s, non-decreasing).)")
      .def(py::init([](const py::handle& position, const py::handle& orientation,
                       const py::handle& linear_velocity, const py::handle& angular_velocity,
                       std::uint32_t buttons, double time) {
             DeviceState s;
             s.pose.position = vector3_in(position, "position");
             s.pose.orientation = quaternion_in(orientation, "orientation");
             if (!linear_velocity.is_none()) {
               s.linear_velocity = vector3_in(linear_velocity, "linear_velocity");
               s.has_linear_velocity = true;
             }
             if (!angular_velocity.is_none()) {
               s.angular_velocity = vector3_in(angular_velocity, "angular_velocity");
               s.has_angular_velocity = true;
             }
             s.buttons = buttons;
             s.time = time;
             s.valid = true;
             return s;
           }),
           py::arg("position"), py::arg("orientation") = std::vector<double>{1.0, 0.0, 0.0, 0.0},
           py::arg("linear_velocity") = py::none(), py::arg("angular_velocity") = py::none(),
           py::arg("buttons") = 0, py::arg("time") = 0.0)
      .def_property_readonly("position",
                             [](const DeviceState& s) { return vector_out(s.pose.position); })
      .def_property_readonly(
          "orientation", [](const DeviceState& s) { return quaternion_out(s.pose.orientation); })
      .def_property_readonly("linear_velocity",
                             [](const DeviceState& s) -> py::object {
                               if (!s.has_linear_velocity) return py::none();
                               return vector_out(s.linear_velocity);
                             })
      .def_property_readonly("angular_velocity",
                             [](const DeviceState& s) -> py::object {
                               if (!s.has_angular_velocity) return py::none();
                               return vector_out(s.angular_velocity);
                             })
      .def_readonly("buttons", &DeviceState::buttons)
      .def_readonly("time", &DeviceState::time)
      .def_readonly("valid", &DeviceState::valid);
}

void bind_device_base(py::module_& module) {
  py::class_<haptic::Device, PythonDevice>(module, "Device", R"(A haptic device: a pose to read
and a wrench to write once per haptic cycle (khz::haptic::Device).

Derive from it to run your own device (e.g. the Python binding of your hardware's SDK) in the
haptic loop::

    class MyDevice(kilohertz.haptic.Device):
        def __init__(self):
            super().__init__(kilohertz.haptic.DeviceCapabilities(max_force=5, max_torque=0.1,
                                                                  max_stiffness=2000))
        def open(self): ...            # optional: connect
        def close(self): ...           # optional: disconnect, render zero
        def read(self):                # required: a DeviceState, or None if the read failed
            return kilohertz.haptic.DeviceState(position=[0, 0, 0], time=self.t)
        def write(self, force, torque):   # optional: render force (3,) N and torque (3,) N·m
            return True                # False: the device did not take it

read() and write() run in the haptic cycle with the GIL taken for the call; an exception there
stops the run, which raises it once the devices are closed.)")
      .def(py::init<const DeviceCapabilities&>(), py::arg("capabilities"))
      .def("open", &haptic::Device::open, "Connects (kilohertz.Error if it cannot).")
      .def("close", &haptic::Device::close, "Stops output and disconnects; idempotent.")
      .def_property_readonly("is_open", &haptic::Device::is_open)
      .def_property_readonly("capabilities", &haptic::Device::capabilities,
                             py::return_value_policy::copy)
      .def(
          "read",
          [](haptic::Device& device) -> py::object {
            DeviceState state;
            if (!device.read(state)) return py::none();
            return py::cast(state);
          },
          "The current reading, or None when the device cannot be read.")
      .def(
          "write",
          [](haptic::Device& device, const py::handle& force, const py::handle& torque) {
            return device.write({vector3_in(force, "force"), vector3_in(torque, "torque")});
          },
          py::arg("force"), py::arg("torque") = std::vector<double>(3, 0.0),
          "Renders force (3,) N and torque (3,) N·m until the next write; False if not taken.");
}

std::vector<haptic::TrajectorySample> samples_from(const py::handle& times,
                                                   const py::handle& positions,
                                                   const py::handle& orientations,
                                                   const py::handle& buttons) {
  const auto t = real_matrix(py::array::ensure(times).attr("reshape")(-1, 1), "times", -1, 1);
  const auto p = real_matrix(positions, "positions", t.rows(), 3);
  const auto q = orientations.is_none() ? decltype(t)()
                                        : real_matrix(orientations, "orientations", t.rows(), 4);
  const auto b =
      buttons.is_none()
          ? Eigen::Matrix<int, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>()
          : index_matrix(py::array::ensure(buttons).attr("reshape")(-1, 1), "buttons", 1);
  if (b.size() != 0 && b.rows() != t.rows()) {
    throw py::value_error("buttons: expected one entry per time");
  }
  std::vector<haptic::TrajectorySample> samples(static_cast<std::size_t>(t.rows()));
  for (Eigen::Index i = 0; i < t.rows(); ++i) {
    auto& s = samples[static_cast<std::size_t>(i)];
    s.time = t(i, 0);
    s.pose.position = p.row(i).transpose();
    if (q.size() != 0) {
      s.pose.orientation = Eigen::Quaterniond(q(i, 0), q(i, 1), q(i, 2), q(i, 3));
    }
    if (b.size() != 0) s.buttons = static_cast<std::uint32_t>(b(i, 0));
  }
  return samples;
}

void bind_trajectory_device(py::module_& module) {
  py::enum_<haptic::Playback>(module, "Playback", "How a TrajectoryDevice replays its samples.")
      .value("sample_per_read", haptic::Playback::sample_per_read,
             "Each read returns the next sample, whatever its time.")
      .value("at_nominal_rate", haptic::Playback::at_nominal_rate,
             "Each read advances 1 / nominal_rate and interpolates.");
  py::class_<haptic::TrajectoryDevice, haptic::Device>(module, "TrajectoryDevice", R"(Replays a
recorded trajectory and keeps every wrench written to it (khz::haptic::TrajectoryDevice).)")
      .def(py::init([](const std::filesystem::path& file, haptic::Playback playback) {
             return std::make_unique<haptic::TrajectoryDevice>(
                 file, haptic::TrajectoryDeviceOptions{.playback = playback});
           }),
           py::arg("file"), py::arg("playback") = haptic::Playback::sample_per_read,
           "From a trajectory CSV (t,x,y,z,qw,qx,qy,qz[,buttons]); ParseError names the line.")
      .def(py::init([](const py::handle& times, const py::handle& positions,
                       const py::handle& orientations, const py::handle& buttons,
                       haptic::Playback playback) {
             return std::make_unique<haptic::TrajectoryDevice>(
                 samples_from(times, positions, orientations, buttons),
                 haptic::TrajectoryDeviceOptions{.playback = playback});
           }),
           py::kw_only(), py::arg("times"), py::arg("positions"),
           py::arg("orientations") = py::none(), py::arg("buttons") = py::none(),
           py::arg("playback") = haptic::Playback::sample_per_read,
           R"(From arrays: times (N,) s strictly increasing, positions (N, 3) m, orientations
(N, 4) unit quaternions (w, x, y, z) or None (identity), buttons (N,) or None.)")
      .def_property_readonly("finished", &haptic::TrajectoryDevice::finished,
                             "True once the last sample has been read.")
      .def("rewind", &haptic::TrajectoryDevice::rewind)
      .def_property_readonly(
          "recorded",
          [](const haptic::TrajectoryDevice& device) {
            const auto record = device.recorded();
            const auto n = static_cast<py::ssize_t>(record.size());
            py::array_t<double> times(n), forces({n, py::ssize_t{3}}), torques({n, py::ssize_t{3}});
            for (py::ssize_t i = 0; i < n; ++i) {
              const auto& r = record[static_cast<std::size_t>(i)];
              times.mutable_at(i) = r.time;
              for (int c = 0; c < 3; ++c) {
                forces.mutable_at(i, c) = r.wrench.force[c];
                torques.mutable_at(i, c) = r.wrench.torque[c];
              }
            }
            return py::make_tuple(times, forces, torques);
          },
          "(times (N,), forces (N, 3), torques (N, 3)): every wrench written since open().")
      .def("write_record", &haptic::TrajectoryDevice::write_record, py::arg("file"),
           "Writes the recorded wrenches as CSV.");
}

void bind_simulated_operator(py::module_& module) {
  py::class_<haptic::SimulatedOperator, haptic::Device>(module, "SimulatedOperator", R"(A
simulated device and hand that follows keyframes (khz::haptic::SimulatedOperator): each read
advances one period 1 / nominal_rate under the wrench last written. For a fully configured
operator (hand stiffness, device mass, ...) use kilohertz.scene.make_device({"type": "operator",
...}), which takes the scene file's keys.)")
      .def(py::init([](const py::handle& times, const py::handle& positions,
                       const py::handle& orientations, const py::handle& buttons,
                       const py::object& capabilities) {
             std::vector<haptic::Keyframe> keyframes;
             for (const auto& sample : samples_from(times, positions, orientations, buttons)) {
               keyframes.push_back({sample.time, sample.pose, sample.buttons});
             }
             haptic::SimulatedOperatorOptions options;
             if (!capabilities.is_none())
               options.capabilities = capabilities.cast<DeviceCapabilities>();
             options.validate();
             return std::make_unique<haptic::SimulatedOperator>(
                 haptic::keyframe_target(keyframes), options, haptic::keyframe_buttons(keyframes));
           }),
           py::kw_only(), py::arg("times"), py::arg("positions"),
           py::arg("orientations") = py::none(), py::arg("buttons") = py::none(),
           py::arg("capabilities") = py::none(),
           R"(Keyframes of the hand's target: times (N,) s, positions (N, 3) m, orientations
(N, 4) (w, x, y, z) or None, buttons (N,) held from each keyframe on, or None; capabilities:
a DeviceCapabilities, or None for a PHANToM Premium-like device.)")
      .def_property_readonly("time", &haptic::SimulatedOperator::time, "Simulated time (s).")
      .def_property_readonly(
          "position",
          [](const haptic::SimulatedOperator& o) { return vector_out(o.pose().position); })
      .def_property_readonly(
          "applied_force",
          [](const haptic::SimulatedOperator& o) { return vector_out(o.applied_wrench().force); })
      .def_property_readonly("hand_energy", &haptic::SimulatedOperator::hand_energy,
                             "Energy stored in the hand's springs (J).");
}

}  // namespace

void bind_haptic_devices(py::module_& haptic) {
  bind_capabilities(haptic);
  bind_state(haptic);
  bind_device_base(haptic);
  bind_trajectory_device(haptic);
  bind_simulated_operator(haptic);
}

}  // namespace khz::python
