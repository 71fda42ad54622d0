#include <khz/contact/field/mesh_distance.hpp>
#include <khz/contact/pointshell/pointshell_sampling.hpp>
#include <khz/reduced/meshing/voxelize.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace khz::contact {

namespace {

constexpr int max_cells = 1024;  // reduced::voxelize()'s limit

}  // namespace

Pointshell voxel_pointshell(const TriangleMesh& mesh, double cell_size,
                            const ProgressCallback& progress) {
  validate(mesh);
  if (mesh.num_triangles() == 0) throw MeshError("voxel_pointshell: the mesh has no triangles");
  if (!(cell_size > 0.0) || !std::isfinite(cell_size)) {
    throw Error("voxel_pointshell: cell size " + std::to_string(cell_size) +
                " is not a positive number");
  }
  // The extent voxelize() grids: the triangles' vertices' bounding box.
  Eigen::Vector3d lower = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d upper = -lower;
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    for (int k = 0; k < 3; ++k) {
      lower = lower.cwiseMin(mesh.vertices.row(mesh.triangles(t, k)).transpose());
      upper = upper.cwiseMax(mesh.vertices.row(mesh.triangles(t, k)).transpose());
    }
  }
  const double extent = (upper - lower).maxCoeff();
  if (!(extent > 0.0)) throw Error("voxel_pointshell: the triangles' vertices all coincide");
  const double cells = std::ceil(extent / cell_size);
  if (cells > max_cells) {
    throw Error("voxel_pointshell: cell size " + std::to_string(cell_size) + " needs " +
                std::to_string(cells) + " cells along the longest side, at most " +
                std::to_string(max_cells));
  }
  reduced::VoxelizeOptions options;
  options.resolution = std::max(1, static_cast<int>(cells));
  // Side = resolution × cell_size; ≥ 1 up to rounding, which voxelize() would reject.
  options.enlargement = std::max(1.0, options.resolution * cell_size / extent);
  const reduced::VolumeMesh voxels = reduced::voxelize(mesh, options);

  PointMatrix centres(voxels.num_elements(), 3);
  for (Eigen::Index e = 0; e < voxels.num_elements(); ++e) {
    Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
    for (int a = 0; a < 8; ++a) sum += voxels.vertices.row(voxels.elements(e, a));
    centres.row(e) = sum / 8.0;
  }
  Pointshell pointshell;
  pointshell.normals = inward_normals(MeshDistance(mesh), centres, progress);
  pointshell.points = std::move(centres);
  pointshell.level_ends = {pointshell.points.rows()};
  return pointshell;
}

}  // namespace khz::contact
