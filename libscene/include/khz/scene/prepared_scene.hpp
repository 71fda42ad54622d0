#pragma once
// What prepare_scene() makes of a scene: per object, exactly the runtime data its roles and model
// need (distance fields, point trees, the reduced model), and a record of how each was obtained.

#include <khz/contact/field/deformed_distance_field.hpp>
#include <khz/contact/field/distance_grid.hpp>
#include <khz/contact/tree/deformable_point_tree.hpp>
#include <khz/contact/tree/point_tree.hpp>
#include <khz/reduced/fem/embedding.hpp>
#include <khz/reduced/mesh/mass_properties.hpp>
#include <khz/reduced/subspace/reduced_model.hpp>
#include <khz/scene/export.hpp>
#include <khz/scene/scene_description.hpp>

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace khz::scene {

/// The steps of preparing an object, in the order prepare_scene() takes them. Three are the
/// cached products of content_key.hpp; the volume mesh is cached with the reduced model (under
/// its key); the point tree, the deformed field and the mass properties are built anew at every
/// preparation (see PreparedObject).
enum class PrepareStep {
  volume_mesh,      ///< The reduced model's volume mesh (.msh, Gmsh 2.2 text).
  reduced_model,    ///< The reduced model with its basis (.khzmodel).
  distance_field,   ///< The rest-shape distance field (.khzsdf).
  pointshell,       ///< The pointshell (.khzshell).
  point_tree,       ///< The point tree, rigid or deformable (built).
  deformed_field,   ///< A reduced distance-field object's deformed field (built).
  mass_properties,  ///< A free object's mass, centre of mass and inertia (built).
};

/// "volume_mesh", "reduced_model", "distance_field", "pointshell", "point_tree",
/// "deformed_field" or "mass_properties"; also the cache file names' prefix.
KHZ_SCENE_API std::string_view step_name(PrepareStep step) noexcept;

/// How prepare_scene() obtained one object's product.
struct PrepareRecord {
  /// Where the product came from.
  enum class Origin {
    computed,  ///< Computed and stored in the cache.
    read,      ///< Read from the cache.
    built,     ///< Computed from other products; never cached (cheap, or no file format).
  };
  std::string object;  ///< The object's name.
  PrepareStep step = PrepareStep::distance_field;
  Origin origin = Origin::computed;
  double seconds = 0.0;        ///< Wall time of the computation (with the write) or the read.
  std::filesystem::path file;  ///< The cache file; empty for built products.
  /// Something worth knowing about a computed product that is not an error, e.g. repulsion
  /// levels that did not converge; empty otherwise.
  std::string note;
  /// In a shared preparation (PrepareOptions::group), the process that computed the product
  /// (its rank in the group); -1 otherwise.
  int rank = -1;
};

/// "computed", "read" or "built".
KHZ_SCENE_API std::string_view origin_name(PrepareRecord::Origin origin) noexcept;

/// One object prepared: what a run of the scene needs of it, and nothing else. Every member is
/// null unless the object's roles and model call for it (noted per member).
///
/// Ownership: each product is owned here, on the heap, so its address stays the same when the
/// PreparedObject or PreparedScene moves. Runtime objects that refer to a product — a
/// contact::DeformedFieldState keeps a pointer to its DeformedDistanceField, contact scenes and
/// workspaces keep references to trees and fields — stay valid as long as the PreparedScene
/// lives, moved or not. The products do not refer to each other: DeformedDistanceField and
/// DeformablePointTree own copies of what they were built from (the rest field, the tree, the
/// sampled modes), and use the embedding and basis only while being built.
struct PreparedObject {
  /// Reduced objects: the volume mesh (embedding->mesh()) the basis lives on, ready to embed
  /// points (e.g. a render mesh's vertices, reduced::EmbeddedSurface).
  std::unique_ptr<reduced::MeshEmbedding> embedding;
  /// Reduced objects: the model (basis(), the energy polynomials and the mass), its integrator
  /// defaults set from the object's `model.integrator` (all but acceleration_limit, which the
  /// integrator options take: ObjectDescription::model.integrator).
  std::unique_ptr<reduced::ReducedModel> model;
  /// Rigid objects with the distance_field role: the signed distance field (m, body frame).
  std::unique_ptr<contact::DistanceGrid> field;
  /// Reduced objects with the distance_field role: the deformed field (its rest field is
  /// deformed_field->field(0)). Evaluate it through a contact::DeformedFieldState.
  std::unique_ptr<contact::DeformedDistanceField> deformed_field;
  /// Rigid objects with the pointshell role: the nested point tree (body frame).
  std::unique_ptr<contact::PointTree> tree;
  /// Reduced objects with the pointshell role: the point tree with its modes.
  std::unique_ptr<contact::DeformablePointTree> deformable_tree;
  /// Free objects ("dynamics"): the mass properties of the solid the body-frame surface bounds
  /// at the object's density (or the density that gives its mass).
  std::unique_ptr<reduced::MassProperties> mass_properties;
};

/// Something about a prepared object that is likely a mistake but not an error, e.g. a size that
/// suggests a mesh in millimetres read as metres.
struct PrepareWarning {
  std::string object;   ///< The object's name.
  std::string message;  ///< What looks wrong and which scene key changes it.
};

/// A prepared scene: its description and, for every object in the same order, what was
/// prepared. Movable, not copyable; see PreparedObject for the lifetimes.
struct KHZ_SCENE_API PreparedScene {
  /// The scene as read; objects[i] belongs to description.objects[i].
  SceneDescription description;
  std::vector<PreparedObject> objects;
  /// Every product obtained, in order: object by object, steps in PrepareStep order.
  std::vector<PrepareRecord> records;
  /// What looked implausible (prepare_scene() says which checks run); empty when nothing did.
  std::vector<PrepareWarning> warnings;

  /// How many records have the given origin (computed: 0 when the cache had everything).
  int count(PrepareRecord::Origin origin) const noexcept;
  /// Sum of the records' seconds.
  double total_seconds() const noexcept;
};

}  // namespace khz::scene
