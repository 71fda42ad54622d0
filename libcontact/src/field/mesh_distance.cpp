#include <khz/contact/field/mesh_distance.hpp>

#include "field/mesh_distance_bvh.hpp"
#include "field/mesh_distance_pseudonormals.hpp"

#include <cmath>
#include <limits>
#include <vector>

namespace khz::contact {

struct MeshDistance::Data {
  detail::TriangleBvh bvh;
  std::vector<detail::TrianglePseudonormals> normals;  // mesh order
};

namespace {

const TriangleMesh& checked(const TriangleMesh& mesh) {
  reduced::validate(mesh);
  if (mesh.num_triangles() == 0) throw MeshError("MeshDistance: the mesh has no triangles");
  return mesh;
}

MeshFeature feature_of(detail::TriangleRegion region) {
  if (region == detail::TriangleRegion::face) return MeshFeature::face;
  return region < detail::TriangleRegion::vertex0 ? MeshFeature::edge : MeshFeature::vertex;
}

}  // namespace

MeshDistance::MeshDistance(const TriangleMesh& mesh)
    : m_data(std::make_unique<Data>(
          Data{detail::TriangleBvh(checked(mesh).vertices, mesh.triangles),
               detail::compute_pseudonormals(mesh.vertices, mesh.triangles)})) {}

MeshDistance::~MeshDistance() = default;
MeshDistance::MeshDistance(MeshDistance&&) noexcept = default;
MeshDistance& MeshDistance::operator=(MeshDistance&&) noexcept = default;

ClosestPoint MeshDistance::closest(const Eigen::Vector3d& p) const {
  detail::BvhHit hit;
  ClosestPoint result;
  if (!p.allFinite() || !m_data->bvh.closest(p, std::numeric_limits<double>::infinity(), -1, hit)) {
    result.distance = std::numeric_limits<double>::quiet_NaN();
    return result;
  }
  const detail::BvhTriangle& triangle = m_data->bvh.triangles()[static_cast<std::size_t>(hit.slot)];
  result.point = hit.closest.point;
  result.distance = std::sqrt(hit.squared_distance);
  result.triangle = triangle.index;
  result.feature = feature_of(hit.closest.region);
  result.pseudonormal =
      m_data->normals[static_cast<std::size_t>(triangle.index)].of(hit.closest.region);
  return result;
}

}  // namespace khz::contact
