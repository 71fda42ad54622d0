// `khz info` for scene files: validated by the scene reader, then summarized.
#include "describe_files.hpp"

#include <khz/scene/content_key.hpp>
#include <khz/scene/read_scene.hpp>
#include <khz/scene/scene_names.hpp>

#include <array>
#include <iostream>
#include <string_view>

namespace khz::tool {
namespace {

/// Every product an object can need, in the order they are prepared.
constexpr std::array<scene::Product, 3> products{
    scene::Product::distance_field, scene::Product::pointshell, scene::Product::reduced_model};

void describe_model(const scene::ModelDescription& model) {
  std::ostream& out = info_line("model", 4);
  if (model.type == scene::ModelType::rigid) {
    out << "rigid\n";
    return;
  }
  out << "reduced, " << scene::basis_method_name(model.basis.method)
      << " basis, r = " << model.basis.basis_size();
  if (model.basis.method == scene::BasisMethod::modes) {
    out << ", k = " << model.basis.modal.modes.num_modes;
  }
  out << "\n";
}

void describe_pointshell(const scene::PointshellDescription& pointshell) {
  std::ostream& out = info_line("pointshell", 4)
                      << scene::pointshell_method_name(pointshell.method) << ", ";
  if (pointshell.method == scene::PointshellMethod::repulsion) {
    out << pointshell.repulsion.levels << " levels (" << pointshell.repulsion.first_level_points
        << " points on level 0)\n";
  } else if (pointshell.nested.schedule.max_levels == 0) {
    out << "as many levels as the points fill\n";
  } else {
    out << "at most " << pointshell.nested.schedule.max_levels << " levels\n";
  }
}

void describe_object(const scene::ObjectDescription& object) {
  info_line("object") << object.name << "\n";
  info_line("mesh", 4) << object.mesh << "\n";
  info_line("roles", 4) << (object.roles.pointshell ? "pointshell" : "")
                        << (object.roles.pointshell && object.roles.distance_field ? ", " : "")
                        << (object.roles.distance_field ? "distance_field" : "") << "\n";
  describe_model(object.model);
  if (object.uses_field()) {
    info_line("field", 4) << object.field.distance.cells << " cells per axis\n";
  }
  if (object.roles.pointshell) describe_pointshell(object.pointshell);
  std::ostream& out = info_line("products", 4);
  std::string_view separator;
  for (const scene::Product product : products) {
    if (!scene::needs_product(object, product)) continue;
    out << separator << scene::product_name(product);
    separator = ", ";
  }
  out << "\n";
}

void describe_device(const scene::DeviceDescription& device) {
  std::ostream& out = info_line("device") << scene::device_type_name(device.type);
  switch (device.type) {
    case scene::DeviceType::null:
      out << " (a fixed pose)";
      break;
    case scene::DeviceType::trajectory:
      out << ", file " << device.trajectory_file;
      break;
    case scene::DeviceType::simulated_operator:
      out << ", " << device.keyframes.size()
          << " keyframe(s), the last at t = " << device.keyframes.back().time << " s";
      break;
    case scene::DeviceType::hardware:
      out << ", backend \"" << device.hardware_name << "\"";
      break;
  }
  out << "\n";
}

/// The rate and how long the scene runs: loop.duration, or what ends it when that is 0.
void describe_loop(const scene::SceneDescription& description) {
  std::ostream& out = info_line("loop") << description.loop.rate_hz << " Hz, ";
  if (description.duration > 0.0) {
    out << "for " << description.duration << " s\n";
    return;
  }
  bool trajectory = false, keyframes = false;
  for (const scene::HapticDescription& hand : description.haptic) {
    trajectory = trajectory || hand.device.type == scene::DeviceType::trajectory;
    keyframes = keyframes || hand.device.type == scene::DeviceType::simulated_operator;
  }
  out << (trajectory && keyframes ? "until the last trajectory or keyframe ends\n"
          : trajectory            ? "until the trajectory ends\n"
          : keyframes             ? "until the last keyframe\n"
                                  : "until interrupted\n");
}

}  // namespace

void describe_scene_file(const std::string& file) {
  const scene::SceneDescription description = scene::read_scene(file);
  info_line("kind") << "Kilohertz scene file, version " << description.version << "\n";
  if (!description.description.empty()) {
    info_line("description") << description.description << "\n";
  }
  info_line("objects") << description.objects.size() << "\n";
  for (const scene::ObjectDescription& object : description.objects) {
    describe_object(object);
  }
  for (const scene::HapticDescription& haptic : description.haptic) {
    std::ostream& out = info_line("haptic")
                        << haptic.object << " as its "
                        << (haptic.role == contact::HapticObject::pointshell ? "pointshell"
                                                                             : "distance_field")
                        << ", grasped at ";
    if (haptic.grasp_at_centre) {
      out << "the centre of its bounding box\n";
    } else {
      out << point_text(haptic.grasp_point) << " m (body frame)\n";
    }
    describe_device(haptic.device);
  }
  describe_loop(description);
}

}  // namespace khz::tool
