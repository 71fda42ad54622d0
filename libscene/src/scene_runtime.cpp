#include <khz/contact/field/deformed_distance_field.hpp>
#include <khz/reduced/errors.hpp>
#include <khz/reduced/subspace/embedded_surface.hpp>
#include <khz/reduced/subspace/polynomial_forces.hpp>
#include <khz/reduced/subspace/reduced_newmark.hpp>
#include <khz/scene/body_mesh.hpp>
#include <khz/scene/make_device.hpp>
#include <khz/scene/scene_runtime.hpp>

#include <algorithm>
#include <string>
#include <utility>

namespace khz::scene {

namespace {

/// One object's runtime state.
struct Object {
  reduced::TriangleMesh surface;
  std::unique_ptr<reduced::PolynomialForces> forces;
  std::unique_ptr<reduced::ReducedIntegrator> integrator;
  std::unique_ptr<contact::DeformedFieldState> field_state;
  std::unique_ptr<reduced::EmbeddedSurface> embedded_surface;  // on first deformed_vertices()
};

/// The object's runtime state and its World body.
haptic::Body make_body(const ObjectDescription& description, const PreparedObject& products,
                       Object& object) {
  object.surface = read_body_mesh(description);
  haptic::Body body;
  body.name = description.name;
  body.pose = haptic::held_body_pose(description.pose, Eigen::Vector3d::Zero());
  if (products.model != nullptr) {
    const reduced::ReducedModel& model = *products.model;
    object.forces = std::make_unique<reduced::PolynomialForces>(model.energy_polynomial());
    reduced::ReducedNewmarkOptions options = model.defaults().newmark_options();
    options.acceleration_limit = description.model.integrator.acceleration_limit;
    object.integrator = reduced::make_reduced_newmark(*object.forces, model.mass(), options);
    body.integrator = object.integrator.get();
  }
  if (products.tree != nullptr) body.pointshell = products.tree.get();
  if (products.deformable_tree != nullptr) body.pointshell = products.deformable_tree.get();
  if (products.field != nullptr) body.field = products.field.get();
  if (products.deformed_field != nullptr) {
    object.field_state = std::make_unique<contact::DeformedFieldState>(*products.deformed_field);
    body.field = object.field_state.get();
  }
  if (description.dynamics) {
    if (products.mass_properties == nullptr) {
      throw reduced::Error("SceneRuntime: free object \"" + description.name +
                           "\" was prepared without its mass properties");
    }
    const reduced::MassProperties& mass = *products.mass_properties;
    haptic::BodyDynamics& dynamics = body.dynamics.emplace();
    dynamics.inertia.mass = mass.mass;
    dynamics.inertia.centre = mass.centre;
    dynamics.inertia.inertia = mass.inertia;
    dynamics.velocity = description.dynamics->velocity;
    dynamics.angular_velocity = description.dynamics->angular_velocity;
  }
  return body;
}

/// The grasp point a hand asks for: its own, or the centre of its object's bounding box.
Eigen::Vector3d grasp_point(const HapticDescription& hand, const reduced::TriangleMesh& surface) {
  if (!hand.grasp_at_centre) return hand.grasp_point;
  return 0.5 * (surface.vertices.colwise().minCoeff() + surface.vertices.colwise().maxCoeff())
                   .transpose();
}

}  // namespace

struct SceneRuntime::Data {
  const PreparedScene& prepared;
  std::vector<Object> objects;
  std::vector<Eigen::Vector3d> grasps;
  std::vector<std::unique_ptr<haptic::Device>> owned_devices;  // the scene's, made here
  std::vector<std::unique_ptr<haptic::SafeDevice>> devices;
  std::unique_ptr<haptic::World> world;
  double natural_duration = 0.0;

  Object& object(int index) { return objects.at(static_cast<std::size_t>(index)); }
};

namespace {

/// The scene's device description of every hand.
std::vector<DeviceDescription> scene_devices(const SceneDescription& scene) {
  std::vector<DeviceDescription> devices;
  for (const HapticDescription& hand : scene.haptic) devices.push_back(hand.device);
  return devices;
}

/// `devices`, checked to have one entry per hand of `scene`.
template <typename T>
std::span<T> one_per_hand(std::span<T> devices, const SceneDescription& scene) {
  if (devices.size() != scene.haptic.size()) {
    throw reduced::Error("SceneRuntime: the scene has " + std::to_string(scene.haptic.size()) +
                         " hand(s) but " + std::to_string(devices.size()) +
                         " device(s) were given");
  }
  return devices;
}

}  // namespace

SceneRuntime::SceneRuntime(const PreparedScene& prepared)
    : SceneRuntime(prepared, scene_devices(prepared.description), {}) {}

SceneRuntime::SceneRuntime(const PreparedScene& prepared, std::vector<DeviceDescription> devices)
    : SceneRuntime(prepared, std::move(devices), {}) {}

SceneRuntime::SceneRuntime(const PreparedScene& prepared, std::span<haptic::Device* const> devices)
    : SceneRuntime(prepared, scene_devices(prepared.description),
                   one_per_hand(devices, prepared.description)) {}

SceneRuntime::SceneRuntime(const PreparedScene& prepared, std::vector<DeviceDescription> devices,
                           std::span<haptic::Device* const> borrowed)
    : m_data(std::make_unique<Data>(Data{prepared, {}, {}, {}, {}, {}, 0.0})) {
  Data& d = *m_data;
  const SceneDescription& scene = prepared.description;
  const std::size_t hands = scene.haptic.size();
  one_per_hand(std::span(devices), scene);
  if (prepared.objects.size() != scene.objects.size()) {
    throw reduced::Error("SceneRuntime: the prepared scene has " +
                         std::to_string(prepared.objects.size()) + " objects' products for " +
                         std::to_string(scene.objects.size()) + " objects");
  }

  d.objects.resize(scene.objects.size());
  std::vector<haptic::Body> bodies;
  for (std::size_t i = 0; i < scene.objects.size(); ++i) {
    bodies.push_back(make_body(scene.objects[i], prepared.objects[i], d.objects[i]));
  }

  std::vector<haptic::Hand> world_hands;
  for (std::size_t h = 0; h < hands; ++h) {
    const HapticDescription& description = scene.haptic[h];
    haptic::Device* device = borrowed.empty() ? nullptr : borrowed[h];
    if (device == nullptr) {
      d.owned_devices.push_back(make_device(devices[h]));
      device = d.owned_devices.back().get();
      d.natural_duration = std::max(d.natural_duration, device_duration(devices[h], *device));
    }
    d.devices.push_back(
        std::make_unique<haptic::SafeDevice>(*device, devices[h].safety, devices[h].mapping));
    d.grasps.push_back(grasp_point(description, d.object(description.object_index).surface));
    haptic::Hand hand;
    hand.body = description.object_index;
    hand.grasp_in_body = d.grasps.back();
    hand.device = d.devices.back().get();
    hand.coupling = scene.coupling;
    hand.role = description.role;
    hand.grasp_button = description.grasp_button;
    world_hands.push_back(hand);
  }
  if (scene.duration > 0.0) d.natural_duration = scene.duration;
  d.world =
      std::make_unique<haptic::World>(std::move(bodies), std::move(world_hands), scene.contact);
  d.world->set_dynamics(scene.dynamics);
  for (const PairDescription& pair : scene.pairs) {
    d.world->set_pair_friction(pair.object_indices[0], pair.object_indices[1], pair.friction);
  }
  // Each coupling starts at its grasp frame as the scene writes it (the pose's own quaternion),
  // not as the World recovers it from the body's rotation matrix, which differs by round-off.
  for (std::size_t h = 0; h < hands; ++h) {
    const HapticDescription& hand = scene.haptic[h];
    haptic::Pose start = scene.objects[static_cast<std::size_t>(hand.object_index)].pose;
    start.position += start.orientation * d.grasps[h];
    d.world->coupling(static_cast<int>(h)).reset(start);
  }
}

SceneRuntime::~SceneRuntime() = default;

const PreparedScene& SceneRuntime::prepared() const noexcept { return m_data->prepared; }
const SceneDescription& SceneRuntime::description() const noexcept {
  return m_data->prepared.description;
}
haptic::World& SceneRuntime::world() noexcept { return *m_data->world; }
const haptic::World& SceneRuntime::world() const noexcept { return *m_data->world; }
int SceneRuntime::hand_count() const noexcept { return static_cast<int>(m_data->devices.size()); }
int SceneRuntime::held_object(int hand) const noexcept {
  return description().haptic[static_cast<std::size_t>(hand)].object_index;
}
const Eigen::Vector3d& SceneRuntime::grasp_in_body(int hand) const noexcept {
  return m_data->grasps[static_cast<std::size_t>(hand)];
}
haptic::SafeDevice& SceneRuntime::device(int hand) noexcept {
  return *m_data->devices[static_cast<std::size_t>(hand)];
}
haptic::Device& SceneRuntime::raw_device(int hand) noexcept { return device(hand).device(); }
double SceneRuntime::natural_duration() const noexcept { return m_data->natural_duration; }

void SceneRuntime::open_devices() {
  std::size_t opened = 0;
  try {
    for (; opened < m_data->devices.size(); ++opened) m_data->devices[opened]->open();
  } catch (...) {
    while (opened > 0) m_data->devices[--opened]->close();
    throw;
  }
}

void SceneRuntime::close_devices() noexcept {
  for (const std::unique_ptr<haptic::SafeDevice>& device : m_data->devices) device->close();
}

const reduced::TriangleMesh& SceneRuntime::surface(int object) const noexcept {
  return m_data->objects[static_cast<std::size_t>(object)].surface;
}

const Eigen::Isometry3d& SceneRuntime::pose(int object) const noexcept {
  return m_data->world->bodies()[static_cast<std::size_t>(object)].pose;
}

Eigen::VectorXd SceneRuntime::coordinates(int object) const {
  const reduced::ReducedIntegrator* integrator = this->integrator(object);
  return integrator != nullptr ? integrator->coordinates() : Eigen::VectorXd();
}

const reduced::ReducedIntegrator* SceneRuntime::integrator(int object) const noexcept {
  return m_data->objects[static_cast<std::size_t>(object)].integrator.get();
}

void SceneRuntime::set_coordinates(int object, const Eigen::VectorXd& q) {
  Object& o = m_data->object(object);
  const std::string name =
      "object \"" + description().objects.at(static_cast<std::size_t>(object)).name + "\"";
  if (o.integrator == nullptr) throw reduced::Error("set_coordinates: " + name + " is rigid");
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(q.size());
  o.integrator->set_state(q, zero, zero);
  if (o.field_state != nullptr && !o.field_state->update(q)) {
    throw reduced::Error("set_coordinates: the deformed field of " + name + " refuses this q");
  }
}

reduced::VertexMatrix SceneRuntime::deformed_vertices(int object) {
  Object& o = m_data->object(object);
  if (o.integrator == nullptr) return o.surface.vertices;
  if (o.embedded_surface == nullptr) {
    const PreparedObject& products = prepared().objects[static_cast<std::size_t>(object)];
    o.embedded_surface = std::make_unique<reduced::EmbeddedSurface>(
        *products.embedding, o.surface, products.model->basis().vectors);
  }
  reduced::VertexMatrix vertices(o.surface.vertices.rows(), 3);
  o.embedded_surface->deformed_positions(o.integrator->coordinates(), vertices);
  return vertices;
}

}  // namespace khz::scene
