// kilohertz.haptic: static virtual coupling (thesis §4.1–§4.10) stepped from Python with a
// contact query's result.

#include <khz/contact/query/contact_result.hpp>
#include <khz/haptic/coupling/coupling_options.hpp>
#include <khz/haptic/coupling/virtual_coupling.hpp>

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <string>

#include "arrays.hpp"
#include "bindings.hpp"

namespace khz::python {

namespace {

using haptic::CouplingOptions;
using haptic::VirtualCoupling;

haptic::Pose pose_from(const py::handle& position, const py::handle& orientation) {
  return {vector3_in(position, "position"), quaternion_in(orientation, "orientation")};
}

py::dict step_out(const haptic::CouplingStep& s) {
  py::dict d;
  d["simulation_position"] = vector_out(s.simulation.position);
  d["simulation_orientation"] = quaternion_out(s.simulation.orientation);
  d["rendered_force"] = vector_out(s.rendered.force);
  d["rendered_torque"] = vector_out(s.rendered.torque);
  d["coupling_force"] = vector_out(s.coupling.force);
  d["coupling_torque"] = vector_out(s.coupling.torque);
  d["residual_force"] = vector_out(s.residual.force);
  d["residual_torque"] = vector_out(s.residual.torque);
  d["degenerate_dimension"] = s.degenerate_dimension;
  d["coupling_saturated"] = s.coupling_saturated;
  d["force_clamped"] = s.force_clamped;
  d["torque_clamped"] = s.torque_clamped;
  d["speed_limited"] = s.speed_limited;
  d["angular_speed_limited"] = s.angular_speed_limited;
  d["valid"] = s.valid;
  return d;
}

}  // namespace

void bind_haptic_coupling(py::module_& module) {
  constexpr double unlimited = CouplingOptions::unlimited;
  py::class_<CouplingOptions>(module, "CouplingOptions", R"(Virtual coupling settings
(khz::haptic::CouplingOptions; docs/HAPTICS.md).)")
      .def(py::init([](double stiffness, double torque_stiffness, double static_damping,
                       double period, double max_speed, double max_angular_speed,
                       double saturation_force, double object_radius, double rotation_length,
                       double max_rendered_force, double max_rendered_torque,
                       double device_max_stiffness) {
             CouplingOptions o;
             o.stiffness = stiffness;
             o.torque_stiffness = torque_stiffness;
             o.static_damping = static_damping;
             o.period = period;
             o.max_speed = max_speed;
             o.max_angular_speed = max_angular_speed;
             o.saturation_force = saturation_force;
             o.object_radius = object_radius;
             o.rotation_length = rotation_length;
             o.max_rendered_force = max_rendered_force;
             o.max_rendered_torque = max_rendered_torque;
             o.device_max_stiffness = device_max_stiffness;
             o.validate();
             return o;
           }),
           py::kw_only(), py::arg("stiffness") = 500.0, py::arg("torque_stiffness") = 1.0,
           py::arg("static_damping") = 0.5, py::arg("period") = 1e-3, py::arg("max_speed") = 0.6,
           py::arg("max_angular_speed") = 2.0 * 3.141592653589793,
           py::arg("saturation_force") = unlimited, py::arg("object_radius") = unlimited,
           py::arg("rotation_length") = 0.0, py::arg("max_rendered_force") = unlimited,
           py::arg("max_rendered_torque") = unlimited, py::arg("device_max_stiffness") = unlimited,
           R"(stiffness k_VC (N/m), torque_stiffness (N·m/rad), static_damping in [0, 1), period
(s), max_speed (m/s) and max_angular_speed (rad/s) per cycle limits, saturation_force (N),
object_radius and rotation_length (m), max_rendered_force (N) and _torque (N·m),
device_max_stiffness (N/m). Raises Error naming an invalid value.)")
      .def_readonly("stiffness", &CouplingOptions::stiffness)
      .def_readonly("period", &CouplingOptions::period);
  py::class_<VirtualCoupling>(module, "VirtualCoupling", R"(Static virtual coupling between the
manipulandum and the simulation object (thesis §4.1–§4.10; khz::haptic::VirtualCoupling). Each
cycle: query contact at simulation pose, then step() with the manipulandum pose and that result.)")
      .def(py::init([](const CouplingOptions& options, const py::handle& position,
                       const py::handle& orientation) {
             return VirtualCoupling(options, pose_from(position, orientation));
           }),
           py::arg("options") = CouplingOptions{},
           py::arg("position") = std::vector<double>(3, 0.0),
           py::arg("orientation") = std::vector<double>{1.0, 0.0, 0.0, 0.0},
           "Starts the simulation object at position (m) and orientation (w, x, y, z).")
      .def_property_readonly(
          "simulation_position",
          [](const VirtualCoupling& c) { return vector_out(c.simulation_pose().position); })
      .def_property_readonly(
          "simulation_orientation",
          [](const VirtualCoupling& c) { return quaternion_out(c.simulation_pose().orientation); })
      .def(
          "step",
          [](VirtualCoupling& coupling, const py::handle& position, const py::handle& orientation,
             const py::object& contact) {
            const haptic::Pose manipulandum = pose_from(position, orientation);
            const contact::ContactWrench none;
            const contact::ContactWrench& wrench =
                contact.is_none() ? none : contact.cast<const contact::ContactResult&>();
            return step_out(coupling.step(manipulandum, wrench));
          },
          py::arg("position"), py::arg("orientation") = std::vector<double>{1.0, 0.0, 0.0, 0.0},
          py::arg("contact") = py::none(),
          R"(One coupling step toward the manipulandum pose under the contact query's result (a
kilohertz.contact.ContactResult at the simulation pose, grasp point at its position; None: no
contact). Returns a dict: simulation_position/orientation after the step, rendered_force/torque
for the device, coupling_ and residual_ wrenches, degenerate_dimension and the limit flags.)")
      .def(
          "reset",
          [](VirtualCoupling& coupling, const py::handle& position, const py::handle& orientation) {
            return coupling.reset(pose_from(position, orientation));
          },
          py::arg("position"), py::arg("orientation") = std::vector<double>{1.0, 0.0, 0.0, 0.0});
}

}  // namespace khz::python
