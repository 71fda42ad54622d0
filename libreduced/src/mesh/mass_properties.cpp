#include <khz/reduced/errors.hpp>
#include <khz/reduced/mesh/mass_properties.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <string>

namespace khz::reduced {

MassProperties mass_properties(const TriangleMesh& mesh, double density) {
  if (!(std::isfinite(density) && density > 0.0)) {
    throw Error("mass_properties: the density must be finite and > 0 (kg/m³), got " +
                std::to_string(density));
  }
  validate(mesh);
  // Moments about the first vertex, not the origin, so that a mesh far from its origin loses no
  // digits: ∫ 1, ∫ x and ∫ x xᵀ over each tetrahedron (o, a, b, c), with o the reference point,
  // are V, V (a + b + c) / 4 and V/20 (a aᵀ + b bᵀ + c cᵀ + s sᵀ), s = a + b + c.
  const Eigen::Vector3d reference = mesh.num_vertices() > 0
                                        ? Eigen::Vector3d(mesh.vertices.row(0).transpose())
                                        : Eigen::Vector3d::Zero();
  double six_volume = 0.0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();   // 24 ∫ x
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();  // 120 ∫ x xᵀ
  for (Eigen::Index t = 0; t < mesh.num_triangles(); ++t) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.triangles(t, 0)).transpose() - reference;
    const Eigen::Vector3d b = mesh.vertices.row(mesh.triangles(t, 1)).transpose() - reference;
    const Eigen::Vector3d c = mesh.vertices.row(mesh.triangles(t, 2)).transpose() - reference;
    const double det = a.dot(b.cross(c));  // 6 V
    const Eigen::Vector3d s = a + b + c;
    six_volume += det;
    first += det * s;
    second += det * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  const double volume = six_volume / 6.0;
  if (!(volume > 0.0) || !std::isfinite(volume)) {
    throw MeshError("mass_properties: the mesh encloses no positive volume (signed volume " +
                    std::to_string(volume) +
                    "): it must be closed and oriented outwards ('khz repair' orients and "
                    "closes one)");
  }
  MassProperties result;
  result.volume = volume;
  result.mass = density * volume;
  const Eigen::Vector3d centre = first / (24.0 * volume);  // relative to the reference
  // ∫ (x − c)(x − c)ᵀ = ∫ x xᵀ − V c cᵀ, then I = ρ (tr C · 1 − C).
  const Eigen::Matrix3d spread = second / 120.0 - volume * centre * centre.transpose();
  result.centre = centre + reference;
  result.inertia = density * (spread.trace() * Eigen::Matrix3d::Identity() - spread);
  return result;
}

}  // namespace khz::reduced
