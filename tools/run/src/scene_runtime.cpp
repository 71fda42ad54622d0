#include <khz/haptic/device/null_device.hpp>
#include <khz/haptic/device/simulated_operator.hpp>
#include <khz/haptic/device/trajectory_device.hpp>
#include <khz/reduced/subspace/embedded_surface.hpp>
#include <khz/reduced/subspace/reduced_newmark.hpp>
#include <khz/run/scene_runtime.hpp>
#include <khz/scene/body_mesh.hpp>
#include <khz/scene/read_scene.hpp>

#include <string>
#include <utility>

namespace khz::run {

/// One scene object's runtime state.
struct SceneRuntime::Object {
  reduced::TriangleMesh surface;
  std::unique_ptr<reduced::PolynomialForces> forces;
  std::unique_ptr<reduced::ReducedIntegrator> integrator;
  std::unique_ptr<contact::DeformedFieldState> field_state;
  std::unique_ptr<reduced::EmbeddedSurface> embedded_surface;  // on first deformed_vertices()
};

scene::DeviceDescription choose_device(const scene::SceneDescription& scene,
                                       const DeviceChoice& choice) {
  const int replacements = static_cast<int>(!choice.trajectory.empty()) +
                           static_cast<int>(!choice.operator_script.empty()) +
                           static_cast<int>(!choice.hardware.empty());
  if (replacements > 1) {
    throw reduced::Error("choose at most one of a trajectory, an operator script and a device");
  }
  scene::DeviceDescription device = scene.device;
  if (!choice.operator_script.empty()) {
    return scene::read_device_file(choice.operator_script, scene.loop.rate_hz);
  }
  if (!choice.trajectory.empty()) {
    if (device.type != scene::DeviceType::trajectory) {
      device.capabilities = haptic::TrajectoryDevice::default_capabilities();
      device.capabilities.nominal_rate = scene.loop.rate_hz;
      device.trajectory = {};
    }
    device.type = scene::DeviceType::trajectory;
    device.trajectory_file = choice.trajectory.string();
    device.trajectory_path = std::filesystem::absolute(choice.trajectory);
  }
  if (!choice.hardware.empty()) {
    device.type = scene::DeviceType::hardware;
    device.hardware_name = choice.hardware;
  }
  return device;
}

std::unique_ptr<haptic::Device> make_device(const scene::DeviceDescription& device) {
  switch (device.type) {
    case scene::DeviceType::null: {
      auto null = std::make_unique<haptic::NullDevice>(device.capabilities);
      null->set_pose(device.null_pose);
      return null;
    }
    case scene::DeviceType::trajectory:
      return std::make_unique<haptic::TrajectoryDevice>(device.trajectory_path, device.trajectory,
                                                        device.capabilities);
    case scene::DeviceType::simulated_operator: {
      haptic::SimulatedOperatorOptions options = device.simulated_operator;
      options.capabilities = device.capabilities;
      return std::make_unique<haptic::SimulatedOperator>(haptic::keyframe_target(device.keyframes),
                                                         options);
    }
    case scene::DeviceType::hardware:
      break;
  }
  throw reduced::Error("device \"" + device.hardware_name +
                       "\": khz has no hardware backends built in; link one of the adapters in "
                       "examples/device_adapters/ into your own program (docs/DEVICES.md)");
}

namespace {

/// The last time the device description plays to (s), 0 if it has none.
double device_duration(const scene::DeviceDescription& device, const haptic::Device& made) {
  if (device.type == scene::DeviceType::simulated_operator) return device.keyframes.back().time;
  if (const auto* trajectory = dynamic_cast<const haptic::TrajectoryDevice*>(&made)) {
    const double period = 1.0 / device.capabilities.nominal_rate;
    return device.trajectory.playback == haptic::Playback::sample_per_read
               ? period * static_cast<double>(trajectory->samples().size())
               : trajectory->samples().back().time - trajectory->samples().front().time;
  }
  return 0.0;
}

Eigen::Isometry3d to_isometry(const haptic::Pose& pose) {
  Eigen::Isometry3d result = Eigen::Isometry3d::Identity();
  result.linear() = pose.orientation.normalized().toRotationMatrix();
  result.translation() = pose.position;
  return result;
}

}  // namespace

SceneRuntime::SceneRuntime(const scene::PreparedScene& prepared,
                           const scene::DeviceDescription& device)
    : SceneRuntime(prepared) {
  m_device = make_device(device);
  attach(*m_device, device.safety, device.mapping);
  const double duration = prepared.description.duration;
  m_natural_duration = duration > 0.0 ? duration : device_duration(device, *m_device);
}

SceneRuntime::SceneRuntime(const scene::PreparedScene& prepared, haptic::Device& device,
                           const haptic::SafetyOptions& safety,
                           const haptic::WorkspaceMapping& mapping)
    : SceneRuntime(prepared) {
  attach(device, safety, mapping);
  m_natural_duration = prepared.description.duration;
}

SceneRuntime::SceneRuntime(const scene::PreparedScene& prepared) : m_prepared(prepared) {
  const scene::SceneDescription& scene = prepared.description;
  std::vector<ContactBody> bodies;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    const scene::ObjectDescription& description = scene.objects[i];
    const scene::PreparedObject& products = prepared.objects[i];
    auto object = std::make_unique<Object>();
    object->surface = scene::read_body_mesh(description);
    ContactBody body;
    body.pose = to_isometry(description.pose);
    if (products.model != nullptr) {
      const reduced::ReducedModel& model = *products.model;
      object->forces = std::make_unique<reduced::PolynomialForces>(model.energy_polynomial());
      reduced::ReducedNewmarkOptions options = model.defaults().newmark_options();
      options.acceleration_limit = description.model.integrator.acceleration_limit;
      object->integrator =
          std::make_unique<reduced::ReducedNewmark>(*object->forces, model.mass(), options);
      body.integrator = object->integrator.get();
    }
    if (products.tree != nullptr) body.tree = products.tree.get();
    if (products.deformable_tree != nullptr) body.tree = products.deformable_tree.get();
    if (products.field != nullptr) body.field = products.field.get();
    if (products.deformed_field != nullptr) {
      object->field_state = std::make_unique<contact::DeformedFieldState>(*products.deformed_field);
      body.field = object->field_state.get();
    }
    bodies.push_back(body);
    m_objects.push_back(std::move(object));
  }

  const int held = scene.haptic.object_index;
  if (scene.haptic.grasp_at_centre) {
    const reduced::TriangleMesh& surface = this->surface(held);
    m_grasp_in_body =
        0.5 *
        (surface.vertices.colwise().minCoeff() + surface.vertices.colwise().maxCoeff()).transpose();
  } else {
    m_grasp_in_body = scene.haptic.grasp_point;
  }
  m_contact =
      std::make_unique<SceneContact>(std::move(bodies), held, m_grasp_in_body, scene.contact);
}

void SceneRuntime::attach(haptic::Device& device, const haptic::SafetyOptions& safety,
                          const haptic::WorkspaceMapping& mapping) {
  m_safe_device = std::make_unique<haptic::SafeDevice>(device, safety, mapping);
  const scene::SceneDescription& scene = m_prepared.description;
  haptic::Pose start = scene.haptic_object().pose;
  start.position += start.orientation * m_grasp_in_body;
  m_coupling = std::make_unique<haptic::VirtualCoupling>(scene.coupling, start);
  m_cycle = std::make_unique<haptic::HapticCycle>(*m_safe_device, *m_coupling, *m_contact);
}

SceneRuntime::~SceneRuntime() = default;

const reduced::TriangleMesh& SceneRuntime::surface(int object) const noexcept {
  return m_objects[static_cast<std::size_t>(object)]->surface;
}

const Eigen::Isometry3d& SceneRuntime::pose(int object) const noexcept {
  return m_contact->bodies()[static_cast<std::size_t>(object)].pose;
}

Eigen::VectorXd SceneRuntime::coordinates(int object) const {
  const reduced::ReducedIntegrator* integrator = this->integrator(object);
  return integrator != nullptr ? integrator->coordinates() : Eigen::VectorXd();
}

const reduced::ReducedIntegrator* SceneRuntime::integrator(int object) const noexcept {
  return m_objects[static_cast<std::size_t>(object)]->integrator.get();
}

void SceneRuntime::set_coordinates(int object, const Eigen::VectorXd& q) {
  Object& o = *m_objects[static_cast<std::size_t>(object)];
  if (o.integrator == nullptr) {
    throw reduced::Error("set_coordinates: object " + std::to_string(object) + " is rigid");
  }
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(q.size());
  o.integrator->set_state(q, zero, zero);
  if (o.field_state != nullptr && !o.field_state->update(q)) {
    throw reduced::Error("set_coordinates: the deformed field of object " + std::to_string(object) +
                         " refuses this q");
  }
}

reduced::VertexMatrix SceneRuntime::deformed_vertices(int object) {
  Object& o = *m_objects[static_cast<std::size_t>(object)];
  if (o.integrator == nullptr) return o.surface.vertices;
  if (o.embedded_surface == nullptr) {
    const scene::PreparedObject& products = m_prepared.objects[static_cast<std::size_t>(object)];
    o.embedded_surface = std::make_unique<reduced::EmbeddedSurface>(
        *products.embedding, o.surface, products.model->basis().vectors);
  }
  reduced::VertexMatrix vertices(o.surface.vertices.rows(), 3);
  o.embedded_surface->deformed_positions(o.integrator->coordinates(), vertices);
  return vertices;
}

}  // namespace khz::run
