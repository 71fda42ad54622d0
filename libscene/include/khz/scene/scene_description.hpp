#pragma once
// A whole scene: the objects, which ones the user holds, where and with which device, and how
// contact, coupling and loop are configured. What the khz tool prepares and runs.

#include <khz/contact/query/contact_options.hpp>
#include <khz/haptic/coupling/coupling_options.hpp>
#include <khz/haptic/loop/haptic_loop.hpp>
#include <khz/haptic/world/dynamics_options.hpp>
#include <khz/scene/device_description.hpp>
#include <khz/scene/object_description.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace khz::scene {

/// One entry of JSON "haptic": an object the user holds and the device holding it (a hand).
struct HapticDescription {
  /// "object" (required): the held object's name. Each object is held by at most one hand.
  std::string object;
  /// Index of that object in SceneDescription::objects (filled in by the reader).
  int object_index = -1;
  /// "role": "pointshell" | "distance_field", the role the held object plays in contact with an
  /// object that could meet it either way (haptic::Hand::role). Default: its only role, or
  /// distance_field (the thesis's convention, §4.1) when it has both.
  contact::HapticObject role = contact::HapticObject::distance_field;
  /// "grasp_point": "centre" (the default: the centre of the held object's bounding box, body
  /// frame) or [x, y, z], a body-frame point (m). The device's tool point holds the object here.
  bool grasp_at_centre = true;
  /// The body-frame grasp point (m) when grasp_at_centre is false.
  Eigen::Vector3d grasp_point = Eigen::Vector3d::Zero();
  /// "grasp_button": the device button (bit index in [0, 31]) that, while held, grasps the
  /// dynamic object the held one touches (haptic::Hand::grasp_button); −1 (the default): none.
  /// Not the device's safety.index_button.
  int grasp_button = -1;
  /// "device" of this entry (a list of hands, version 2), or the scene's top-level "device"
  /// (one hand): a null device by default.
  DeviceDescription device;
};

/// One entry of "contact.pairs": the contact between two objects where it differs from the
/// scene's "contact" block.
struct PairDescription {
  /// "objects" (required): the two objects' names, distinct, one of them held and their roles
  /// meeting (one's pointshell, the other's distance field), so that they touch.
  std::array<std::string, 2> objects;
  /// Their indices in SceneDescription::objects (filled in by the reader).
  std::array<int, 2> object_indices{-1, -1};
  /// "friction": contact::FrictionOptions of this pair as {"static", "kinetic",
  /// "stick_distance"}; a key left out keeps the scene's "contact.friction" value
  /// ("stick_distance" left out everywhere: 0, μ_s times the voxel of the pair's field).
  contact::FrictionOptions friction;
};

/// The description of a scene, as read from a scene file (read_scene()). Plain values:
/// everything the preparation and run steps need, resolved (absolute paths, unit normals and
/// quaternions, derived defaults filled in), and nothing computed from the meshes.
struct SceneDescription {
  /// The scene file (as named to read_scene(); the source name for parse_scene()).
  std::string source;
  /// Directory relative paths were resolved against (absolute).
  std::filesystem::path base_directory;
  /// "version": the format version (optional). 2, the current one, lets "haptic" be a list of
  /// hands, each with its own "device"; version 1 files (one "haptic" object and a top-level
  /// "device") read as before, in either version.
  int version = 2;
  /// "description": free text for people; not used.
  std::string description;
  /// "objects" (required): distinct names; some are held (haptic[i].object), some may be free
  /// rigid bodies (objects[i].dynamics), the others stay at their pose, and every object takes
  /// part in some contact with a held or free one, so there are at least two.
  std::vector<ObjectDescription> objects;
  /// "haptic" (required): the hands, at least one. One object {"object", "role",
  /// "grasp_point"} with the scene's top-level "device", or (version 2) a list of such objects,
  /// each with its own "device" (and no top-level "device").
  std::vector<HapticDescription> haptic;
  /// "contact": contact::ContactOptions with the same JSON names (stiffness, scaling_count,
  /// max_level, gradient, degradation {mode, warm_threshold, budget_microseconds,
  /// cold_fraction, contact_weight}, coherence {enabled, max_translation, max_rotation,
  /// max_deformation, max_field_deformation, max_skip}, friction {static, kinetic,
  /// stick_distance}) and its defaults, for every pair. haptic_object is not a key: the reader
  /// sets it to haptic[0].role (each hand's own role is its HapticDescription::role).
  contact::ContactOptions contact;
  /// "contact.pairs": pairs of objects whose contact differs from "contact" (their friction),
  /// at most one entry per pair.
  std::vector<PairDescription> pairs;
  /// "dynamics" (only with a free object): haptic::DynamicsOptions of the free objects with the
  /// same JSON names and defaults (gravity [x, y, z] m/s², contact_damping s, sleep_speed m/s,
  /// sleep_time s). time_step is not a key: the reader sets it to 1 / loop.rate_hz.
  haptic::DynamicsOptions dynamics;
  /// "coupling": haptic::CouplingOptions with the same JSON names and defaults, for every hand;
  /// the limits that default to unlimited stay unlimited when absent. period is not a key: the
  /// reader sets it to 1 / loop.rate_hz.
  haptic::CouplingOptions coupling;
  /// "loop": haptic::LoopOptions with the same JSON names and defaults (rate_hz,
  /// realtime_priority, priority, cpu); statistics_every is not a key.
  haptic::LoopOptions loop;
  /// "threads": the most threads the scene's preparation runs at once (its precomputations,
  /// CHOLMOD and OpenBLAS; reduced::worker_threads()), ≥ 1. 0 (the default, no key): the
  /// process's setting, which the khz tools take from the environment variable KHZ_THREADS.
  int threads = 0;
  /// "loop.duration": how long to run (s), ≥ 0. 0 (the default): until the longest trajectory
  /// or operator script ends, or until interrupted for null and hardware devices.
  double duration = 0.0;

  /// Whether some object is free (ObjectDescription::is_dynamic()).
  bool has_free_objects() const noexcept {
    return std::any_of(objects.begin(), objects.end(),
                       [](const ObjectDescription& object) { return object.is_dynamic(); });
  }

  /// The object hand `hand` holds. Precondition: a scene returned by the reader.
  /// @throws std::out_of_range for a hand index out of range.
  const ObjectDescription& held_object(int hand = 0) const {
    return objects.at(
        static_cast<std::size_t>(haptic.at(static_cast<std::size_t>(hand)).object_index));
  }
};

}  // namespace khz::scene
