#pragma once
// One object of a scene: its surface mesh, where it starts, the contact roles it plays and how
// its model, distance field and pointshell are made.

#include <khz/haptic/common.hpp>
#include <khz/scene/dynamics_description.hpp>
#include <khz/scene/field_description.hpp>
#include <khz/scene/model_description.hpp>
#include <khz/scene/pointshell_description.hpp>

#include <filesystem>
#include <optional>
#include <string>

namespace khz::scene {

/// JSON object.roles: an array naming "pointshell", "distance_field" or both (at least one).
struct ObjectRoles {
  bool pointshell = false;      ///< Sampled by a pointshell that touches distance fields.
  bool distance_field = false;  ///< Has a distance field that pointshells touch.
};

/// JSON objects[i]. The body frame is the mesh's frame (its file's, or the procedural shape's),
/// scaled and optionally centred; the pose places it in the world.
struct ObjectDescription {
  /// "name" (required): unique in the scene; letters, digits, '_', '-' and '.', not starting
  /// with '.' (the preparation step may use it in file names).
  std::string name;
  /// "mesh" (required): the surface mesh as written in the scene: a file (.obj, .off, .stl,
  /// .ply), relative to the scene file's directory unless absolute; "cgal:NAME" for one of
  /// CGAL's demo meshes (see default_cgal_mesh_dir()); or "shape:SPEC" for a procedural mesh
  /// (procedural_shape(), e.g. "shape:peg:side=0.02"), generated when the object is prepared.
  std::string mesh;
  /// A file `mesh` resolved: absolute and lexically normal. Empty for a procedural shape.
  std::filesystem::path mesh_path;
  /// A procedural shape's spec in canonical form (canonical_shape_spec(): every parameter
  /// written out), e.g. "peg:side=0.02,length=0.08,chamfer=0.001". Empty for a file.
  std::string shape;
  /// "scale": uniform factor from the file's units to metres, > 0. Default 1.
  double scale = 1.0;
  /// "size" (instead of "scale"): the scale is chosen so that the longest side of the mesh's
  /// bounding box becomes this many metres, > 0. Unset by default.
  std::optional<double> size;
  /// "centre": move the body frame's origin to the centre of the mesh's bounding box (after
  /// scaling). Default false: the file's origin is kept.
  bool centre = false;
  /// "fill_holes": close the mesh's holes with reduced::fill_holes() before anything is made
  /// from it, e.g. for a scan with small holes that needs a signed distance field (which an open
  /// mesh is refused). Default false.
  bool fill_holes = false;
  /// "pose": world ← body at the start: {"position": [x, y, z] (m), "rotation": {"axis":
  /// [x, y, z], "degrees": angle}} (right-handed about the axis, which need not be unit).
  /// Default: identity.
  haptic::Pose pose;
  ObjectRoles roles;  ///< "roles" (required).
  /// "model": rigid by default.
  ModelDescription model;
  /// "field": used by the distance_field role and by a repulsion pointshell.
  FieldDescription field;
  /// "pointshell": used by the pointshell role.
  PointshellDescription pointshell;
  /// "dynamics": set for a free rigid body (neither held nor fixed). Unset by default: an object
  /// no hand holds stays at its pose.
  std::optional<DynamicsDescription> dynamics;

  /// True for a reduced deformable model.
  bool is_reduced() const noexcept { return model.type == ModelType::reduced; }
  /// True for a free rigid body ("dynamics").
  bool is_dynamic() const noexcept { return dynamics.has_value(); }
  /// True if the object needs its distance field: it has the distance_field role, or a
  /// repulsion pointshell whose level set the field provides.
  bool uses_field() const noexcept {
    return roles.distance_field ||
           (roles.pointshell && pointshell.method == PointshellMethod::repulsion);
  }
};

}  // namespace khz::scene
