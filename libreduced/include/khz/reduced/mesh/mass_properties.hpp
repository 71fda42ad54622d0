#pragma once
// Mass, centre of mass and inertia tensor of the solid a closed triangle mesh bounds: what a
// free rigid body needs to move (issue 20).

#include <khz/reduced/export.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <Eigen/Core>

namespace khz::reduced {

/// The rigid-body mass properties of a solid of uniform density.
struct MassProperties {
  double volume = 0.0;                                ///< m³ (mesh units cubed).
  double mass = 0.0;                                  ///< kg: density × volume.
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();   ///< Centre of mass, mesh frame (m).
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  ///< About the centre, mesh axes (kg·m²).
};

/// The mass properties of the solid `mesh` bounds, of uniform `density` (kg/m³): exact for the
/// polyhedron, by the divergence theorem (each triangle closes a tetrahedron with the origin, whose
/// volume, first and second moments are summed with their signs; Mirtich 1996 and Eberly's
/// "Polyhedral Mass Properties" derive the same integrals). O(#F), no allocation.
///
/// The mesh must be closed and oriented outwards (TriangleMesh's convention): on an open mesh or
/// a polygon soup the sums describe no solid, which this cannot always tell.
/// @throws MeshError if `mesh` fails validate(), or encloses no positive volume (empty, inside
///         out, or open so that its faces cancel).
/// @throws Error if density is not finite and > 0.
KHZ_REDUCED_API MassProperties mass_properties(const TriangleMesh& mesh, double density);

}  // namespace khz::reduced
