#pragma once
// Angle-weighted pseudonormals of a triangle mesh's faces, edges and vertices (Bærentzen &
// Aanæs 2005): the sign of (p − c)·n with c the closest point of a closed, consistently
// oriented manifold mesh and n the pseudonormal of the feature holding c tells inside from
// outside (thesis §3.8.1, §3.11).

#include <khz/contact/common.hpp>

#include "field/mesh_distance_triangle.hpp"

#include <Eigen/Core>

#include <vector>

namespace khz::contact::detail {

/// The pseudonormals of one triangle's seven features, each a unit vector or zero.
struct TrianglePseudonormals {
  Eigen::Vector3d face;       ///< (b − a) × (c − a) normalized; zero if degenerate.
  Eigen::Vector3d edge[3];    ///< Edge k (corners k, k+1): sum of its faces' normals.
  Eigen::Vector3d vertex[3];  ///< Corner k: its faces' normals weighted by their angles there.

  const Eigen::Vector3d& of(TriangleRegion region) const noexcept {
    const int r = static_cast<int>(region);
    if (region == TriangleRegion::face) return face;
    if (r < static_cast<int>(TriangleRegion::vertex0)) {
      return edge[r - static_cast<int>(TriangleRegion::edge0)];
    }
    return vertex[r - static_cast<int>(TriangleRegion::vertex0)];
  }
};

/// Pseudonormals of every triangle of a validated mesh, in triangle order. Degenerate triangles
/// (is_degenerate_triangle()) contribute to no edge or vertex. Edges are matched by their
/// vertex indices, so an edge with more than two triangles (non-manifold) sums all their
/// normals. A feature whose normals cancel (a fold) or whose triangles are all degenerate gets
/// a zero pseudonormal.
std::vector<TrianglePseudonormals> compute_pseudonormals(const PointMatrix& vertices,
                                                         const TriangleMatrix& triangles);

}  // namespace khz::contact::detail
