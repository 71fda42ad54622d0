#pragma once
// A prepared scene made runnable: its bodies, hands and devices as one haptic::World.

#include <khz/haptic/device/device.hpp>
#include <khz/haptic/device/safe_device.hpp>
#include <khz/haptic/world/world.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>
#include <khz/reduced/subspace/reduced_integrator.hpp>
#include <khz/scene/export.hpp>
#include <khz/scene/prepared_scene.hpp>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <memory>
#include <span>
#include <vector>

namespace khz::scene {

/// Everything a prepared scene needs to run, built once before the loop starts: per object its
/// surface mesh (body frame), and for a reduced one its integrator (reduced::make_reduced_newmark()
/// with the model's defaults) and deformed-field state; per hand ("haptic" entry) its device behind
/// a haptic::SafeDevice with the entry's safety and mapping; and the haptic::World of them all
/// (the scene's contact, coupling and dynamics settings, each hand's grasp point, role and grasp
/// button; a free object ("dynamics") a dynamic body with its prepared mass properties and
/// starting velocities, and its contact.pairs friction). A cycle is
/// world().cycle(); the World's body i is the scene's object i and its hand h the scene's
/// haptic[h].
///
///     scene::SceneRuntime runtime(prepared);
///     runtime.open_devices();
///     for (int i = 0; i < 1000; ++i) {
///       const double t = i * period;
///       runtime.world().cycle(t, t + period, [t] { return t; });  // simulated time
///     }
///     runtime.close_devices();
///
/// The PreparedScene must outlive the runtime. Not copyable or movable (the World refers to its
/// parts). Units: metres, seconds, newtons, as everywhere (docs/SCENES.md).
class KHZ_SCENE_API SceneRuntime {
 public:
  /// Runs with the devices the scene describes (haptic[h].device; make_device()).
  /// @throws reduced::Error (and its kinds) naming the problem: an unreadable mesh, an invalid
  ///         setting the libraries refuse, a hardware device (no backend is built in).
  explicit SceneRuntime(const PreparedScene& prepared);
  /// Runs with these descriptions in place of the scene's devices, one per hand (e.g. the scene
  /// device with another trajectory file).
  /// @throws reduced::Error as above, and if `devices` does not have one entry per hand.
  SceneRuntime(const PreparedScene& prepared, std::vector<DeviceDescription> devices);
  /// Runs with devices the caller owns and drives (e.g. its own hardware, or the viewer's
  /// mouse), one entry per hand: each behind a safety layer with its hand's safety and mapping
  /// from the scene (device(h).set_mapping() changes it); a null entry keeps the scene's device
  /// for that hand. natural_duration() counts only the scene's devices.
  /// @param devices not owned; they must outlive the runtime.
  /// @throws reduced::Error as above, and if `devices` does not have one entry per hand.
  SceneRuntime(const PreparedScene& prepared, std::span<haptic::Device* const> devices);
  ~SceneRuntime();
  SceneRuntime(const SceneRuntime&) = delete;
  SceneRuntime& operator=(const SceneRuntime&) = delete;

  const PreparedScene& prepared() const noexcept;
  const SceneDescription& description() const noexcept;
  /// The World: cycle() runs one haptic cycle of every hand; bodies(), pairs(), pair_result(),
  /// coupling(h), wrench(h) report on it.
  haptic::World& world() noexcept;
  const haptic::World& world() const noexcept;

  /// Number of hands (the scene's "haptic" entries), at least 1.
  int hand_count() const noexcept;
  /// The object hand `hand` holds (an index into description().objects).
  int held_object(int hand = 0) const noexcept;
  /// Hand `hand`'s grasp point (m, body frame of its object): the scene's, or the centre of the
  /// object's bounding box.
  const Eigen::Vector3d& grasp_in_body(int hand = 0) const noexcept;
  /// Hand `hand`'s device behind its safety layer.
  haptic::SafeDevice& device(int hand = 0) noexcept;
  /// The device under hand `hand`'s safety layer (e.g. to ask a TrajectoryDevice whether it
  /// finished).
  haptic::Device& raw_device(int hand = 0) noexcept;
  /// Opens every hand's device (SafeDevice::open()). If one fails, closes those opened and
  /// rethrows. @throws as the device's open().
  void open_devices();
  /// Closes every hand's device.
  void close_devices() noexcept;
  /// How long the scene runs (s): loop.duration, or else the longest of its own devices'
  /// recordings (device_duration()); 0 when neither says (null and hardware devices, devices of
  /// the caller).
  double natural_duration() const noexcept;

  /// Object i's surface mesh in its body frame (read_body_mesh()).
  const reduced::TriangleMesh& surface(int object) const noexcept;
  /// Object i's current pose, world ← body (a held object's at the last cycle or probe).
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
  /// rigid objects. Not for the haptic thread (allocates).
  reduced::VertexMatrix deformed_vertices(int object);

 private:
  struct Data;
  SceneRuntime(const PreparedScene& prepared, std::vector<DeviceDescription> devices,
               std::span<haptic::Device* const> borrowed);
  std::unique_ptr<Data> m_data;
};

}  // namespace khz::scene
