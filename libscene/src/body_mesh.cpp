#include <khz/scene/body_mesh.hpp>

#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/mesh_file.hpp>
#include <khz/reduced/mesh/mesh_repair.hpp>
#include <khz/scene/procedural_shape.hpp>

#include <string>
#include <utility>

namespace khz::scene {

reduced::TriangleMesh to_body_frame(reduced::TriangleMesh file_mesh,
                                    const ObjectDescription& object) {
  reduced::TriangleMesh mesh = std::move(file_mesh);
  if (mesh.vertices.rows() == 0) {
    throw reduced::MeshError("object \"" + object.name + "\": the mesh has no vertices");
  }
  if (object.fill_holes) reduced::fill_holes(mesh);
  const Eigen::RowVector3d low = mesh.vertices.colwise().minCoeff();
  const Eigen::RowVector3d high = mesh.vertices.colwise().maxCoeff();
  double scale = object.scale;
  if (object.size) {
    const double longest = (high - low).maxCoeff();
    if (!(longest > 0.0)) {
      throw reduced::MeshError("object \"" + object.name +
                               "\": \"size\" cannot scale a mesh whose vertices all coincide");
    }
    scale = *object.size / longest;
  }
  mesh.vertices *= scale;
  if (object.centre) {
    const Eigen::RowVector3d centre = 0.5 * (low + high) * scale;
    mesh.vertices.rowwise() -= centre;
  }
  return mesh;
}

reduced::TriangleMesh read_body_mesh(const ObjectDescription& object) {
  return to_body_frame(object.shape.empty() ? reduced::read_triangle_mesh(object.mesh_path)
                                            : procedural_shape(object.shape),
                       object);
}

}  // namespace khz::scene
