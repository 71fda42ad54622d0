#pragma once
// What isosurface() knows beyond the mesh: which grid edge each vertex lies on. The polygon-soup
// pipeline uses it to tell outer level-set components from inner ones on the grid itself
// (polygon_soup_field.cpp).

#include <khz/contact/common.hpp>
#include <khz/contact/field/distance_grid.hpp>

#include <cstdint>
#include <vector>

namespace khz::contact::detail {

/// isosurface(grid, level); if `upper_nodes` is not null, it receives for every vertex the index
/// (GridGeometry::node_index) of the grid node at the larger-value end of the tetrahedron edge the
/// vertex lies on (a node with value ≥ level).
TriangleMesh isosurface(const DistanceGrid& grid, double level,
                        std::vector<std::int64_t>* upper_nodes);

/// The 14 neighbours of a node in the split isosurface() uses: a tetrahedron edge joins nodes
/// whose index offsets (di, dj, dk) are all in {0, 1} or all in {−1, 0}, not all zero. Each row
/// is (di, dj, dk).
inline constexpr int kTetrahedronNeighbours[14][3] = {
    {1, 0, 0},  {0, 1, 0},  {1, 1, 0},   {0, 0, 1},  {1, 0, 1},   {0, 1, 1},   {1, 1, 1},
    {-1, 0, 0}, {0, -1, 0}, {-1, -1, 0}, {0, 0, -1}, {-1, 0, -1}, {0, -1, -1}, {-1, -1, -1}};

}  // namespace khz::contact::detail
