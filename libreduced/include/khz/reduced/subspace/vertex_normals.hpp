#pragma once
// Area-weighted vertex normals of a triangle mesh: the exact normals of a deformed render mesh.

#include <khz/reduced/export.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <Eigen/Core>

namespace khz::reduced {

/// Unit vertex normals of the triangle mesh (`positions`, `triangles`): at each vertex the sum of
/// the cross products (b−a)×(c−a) of the triangles around it (twice each triangle's area times
/// its unit normal, so larger triangles weigh more), normalized. Counter-clockwise triangles seen
/// from outside (the TriangleMesh convention) give outward normals.
///
/// Area weighting commutes with affine maps: a cross product of edges maps under x ↦ A x + t by
/// cof(A) = det(A) A⁻ᵀ, so the normals of A-mapped positions are A⁻ᵀN normalized (det A > 0) —
/// the exact normal transform that the deformation-gradient normals of EmbeddedSurface
/// (thesis eq. 3.8, F N normalized) approximate. Call it on deformed positions for true normals.
///
/// Meant for every rendered frame: writes into the caller-presized `normals` and allocates
/// nothing; serial (a scatter over triangles). A vertex in no triangle, or whose cross products
/// sum to exactly zero, gets (0, 0, 0); non-finite positions give non-finite normals.
/// @param positions #V×3 vertex positions (any length unit).
/// @param triangles #F×3 zero-based vertex indices.
/// @param normals #V×3 output: unit (dimensionless) or zero rows.
/// @throws Error if `normals` does not have #V rows; MeshError naming the first triangle with an
///         index outside [0, #V) (checked before anything is written).
KHZ_REDUCED_API void vertex_normals(const Eigen::Ref<const VertexMatrix>& positions,
                                    const Eigen::Ref<const TriangleMatrix>& triangles,
                                    Eigen::Ref<VertexMatrix> normals);

}  // namespace khz::reduced
