#pragma once
// An object's surface mesh in its body frame: the mesh file's (or procedural shape's) coordinates
// scaled to metres and optionally centred, as the scene describes (docs/SCENES.md, "Frames").

#include <khz/reduced/mesh/triangle_mesh.hpp>
#include <khz/scene/export.hpp>
#include <khz/scene/object_description.hpp>

namespace khz::scene {

/// `file_mesh` (in its file's units) moved into the object's body frame (m): every coordinate
/// multiplied by the scale — `object.scale`, or with `object.size` the factor that makes the
/// longest side of the mesh's bounding box `*object.size` — and then, with `object.centre`, the
/// centre of the scaled bounding box subtracted. Triangles are kept as they are, except that
/// with `object.fill_holes` reduced::fill_holes() first adds those closing the holes.
/// @throws reduced::MeshError if `object.size` is set and the vertices all lie in one point
///         (no side to scale), the mesh has no vertices, or fill_holes() refuses the mesh.
KHZ_SCENE_API reduced::TriangleMesh to_body_frame(reduced::TriangleMesh file_mesh,
                                                  const ObjectDescription& object);

/// The object's surface mesh in its body frame (to_body_frame()): object.mesh_path read (format
/// by extension), or the procedural shape object.shape generated (procedural_shape()).
/// @throws reduced::IoError, ParseError or Error as reduced::read_triangle_mesh(); reduced::Error
///         for an invalid shape spec; reduced::MeshError as to_body_frame().
KHZ_SCENE_API reduced::TriangleMesh read_body_mesh(const ObjectDescription& object);

}  // namespace khz::scene
