#pragma once
// A prepared scene made runnable: the device, the virtual coupling, every deformable object's
// integrator, the contact pairs and the haptic cycle that ties them (thesis Figure 4.2).

#include <khz/haptic/coupling/virtual_coupling.hpp>
#include <khz/haptic/cycle/haptic_cycle.hpp>
#include <khz/haptic/device/device.hpp>
#include <khz/haptic/device/safe_device.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>
#include <khz/reduced/subspace/polynomial_forces.hpp>
#include <khz/run/scene_contact.hpp>
#include <khz/scene/prepared_scene.hpp>

#include <Eigen/Geometry>

#include <memory>
#include <vector>

namespace khz::run {

/// The device a scene runs with: the scene's own "device", or one of these replacing it.
struct DeviceChoice {
  /// `khz run --trajectory FILE`: replay this trajectory CSV (haptic::read_trajectory()) with
  /// the scene device's mapping and safety settings.
  std::filesystem::path trajectory;
  /// `khz run --operator SCRIPT`: a device file (scene::read_device_file(), e.g. an operator's
  /// keyframes) replacing the scene's device entirely.
  std::filesystem::path operator_script;
  /// `khz run --device NAME`: a hardware backend by name. None is built into khz (see
  /// examples/device_adapters/), so naming one fails with a message that says so.
  std::string hardware;
};

/// The scene's device description with `choice` applied.
/// @throws reduced::IoError, scene::SceneError (reading the operator script); reduced::Error if
///         more than one replacement is given.
scene::DeviceDescription choose_device(const scene::SceneDescription& scene,
                                       const DeviceChoice& choice);

/// Makes the device a description asks for (not yet opened).
/// @throws reduced::Error for a hardware device (no backend is built in), or as the device's
///         constructor (e.g. an unreadable trajectory).
std::unique_ptr<haptic::Device> make_device(const scene::DeviceDescription& device);

/// Everything a prepared scene needs to run, built once before the loop starts: one object per
/// scene object (its surface, pose, integrator, deformed-field state), the SceneContact, the
/// device behind the safety layer, the coupling (starting at the held object's grasp frame in
/// its scene pose) and the HapticCycle. The PreparedScene must outlive it. Not copyable or
/// movable (the cycle refers to its parts).
class SceneRuntime {
 public:
  /// @param prepared a prepared scene (scene::prepare_scene()).
  /// @param device the description of the device to run with (choose_device()).
  /// @throws reduced::Error (and its kinds) naming the problem: an unreadable mesh, an invalid
  ///         setting the libraries refuse, a missing hardware backend.
  SceneRuntime(const scene::PreparedScene& prepared, const scene::DeviceDescription& device);
  /// Runs with a device the caller owns and drives (e.g. the viewer's mouse), behind a safety
  /// layer with `safety` and `mapping`; natural_duration() is then loop.duration alone.
  /// @param device not owned; it must outlive the runtime.
  /// @throws reduced::Error (and its kinds) as the other constructor, and if `safety` or
  ///         `mapping` is invalid (haptic::SafeDevice).
  SceneRuntime(const scene::PreparedScene& prepared, haptic::Device& device,
               const haptic::SafetyOptions& safety = {},
               const haptic::WorkspaceMapping& mapping = {});
  ~SceneRuntime();
  SceneRuntime(const SceneRuntime&) = delete;
  SceneRuntime& operator=(const SceneRuntime&) = delete;

  const scene::PreparedScene& prepared() const noexcept { return m_prepared; }
  const scene::SceneDescription& description() const noexcept { return m_prepared.description; }
  int held_object() const noexcept { return description().haptic.object_index; }
  /// The held object's grasp point (m, body frame): the scene's, or its bounding box centre.
  const Eigen::Vector3d& grasp_in_body() const noexcept { return m_grasp_in_body; }
  /// Object i's surface mesh in its body frame (scene::read_body_mesh()).
  const reduced::TriangleMesh& surface(int object) const noexcept;
  /// Object i's current pose, world ← body (the held object's at the last query).
  const Eigen::Isometry3d& pose(int object) const noexcept;
  /// Object i's reduced coordinates q (empty for rigid objects).
  Eigen::VectorXd coordinates(int object) const;
  /// Object i's integrator (null for rigid objects).
  const reduced::ReducedIntegrator* integrator(int object) const noexcept;
  /// Puts reduced object i at rest in configuration q (r entries; velocity and acceleration
  /// zero) and deforms its distance field to it, if it has one: to replay recorded states.
  /// @throws reduced::Error for a rigid object, a q of the wrong size or not finite, or a q
  ///         the deformed field refuses (contact::DeformedFieldState::update()).
  void set_coordinates(int object, const Eigen::VectorXd& q);
  /// Object i's surface deformed to its current q, body frame: u = U q interpolated at the
  /// surface's vertices (reduced::EmbeddedSurface, built on first use); the rest surface for
  /// rigid objects. Not for the haptic thread (allocates on first use).
  reduced::VertexMatrix deformed_vertices(int object);

  SceneContact& contact() noexcept { return *m_contact; }
  const SceneContact& contact() const noexcept { return *m_contact; }
  haptic::SafeDevice& device() noexcept { return *m_safe_device; }
  haptic::VirtualCoupling& coupling() noexcept { return *m_coupling; }
  haptic::HapticCycle& cycle() noexcept { return *m_cycle; }
  const haptic::HapticCycle& cycle() const noexcept { return *m_cycle; }
  /// The device under the safety layer (e.g. to ask a TrajectoryDevice whether it finished).
  haptic::Device& raw_device() noexcept { return m_safe_device->device(); }
  /// How long the scene runs (s): loop.duration, or for a trajectory its last sample's time,
  /// for an operator its last keyframe's; 0 when neither says (null and hardware devices).
  double natural_duration() const noexcept { return m_natural_duration; }

 private:
  struct Object;
  /// Everything but the device: the objects and the contact.
  explicit SceneRuntime(const scene::PreparedScene& prepared);
  /// Puts `device` behind the safety layer and builds the coupling and the cycle.
  void attach(haptic::Device& device, const haptic::SafetyOptions& safety,
              const haptic::WorkspaceMapping& mapping);

  const scene::PreparedScene& m_prepared;
  std::vector<std::unique_ptr<Object>> m_objects;
  Eigen::Vector3d m_grasp_in_body = Eigen::Vector3d::Zero();
  std::unique_ptr<SceneContact> m_contact;
  std::unique_ptr<haptic::Device> m_device;  // null for a caller's device
  std::unique_ptr<haptic::SafeDevice> m_safe_device;
  std::unique_ptr<haptic::VirtualCoupling> m_coupling;
  std::unique_ptr<haptic::HapticCycle> m_cycle;
  double m_natural_duration = 0.0;
};

}  // namespace khz::run
