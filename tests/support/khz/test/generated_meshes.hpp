#pragma once
// Small meshes built in code, so tests do not depend on files for basic cases.

#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <cstdint>

namespace khz::test {

/// Closed, outward-oriented surface of the cube [0,1]³: 8 vertices, 12 triangles.
reduced::TriangleMesh unit_cube_surface();
/// Open unit square in the z = 0 plane: 4 vertices, 2 triangles, 4 boundary edges.
reduced::TriangleMesh unit_square();
/// Closed, outward-oriented UV sphere of radius 1 (2 poles + (stacks−1)·slices vertices).
reduced::TriangleMesh uv_sphere(int slices, int stacks);
/// `count` random triangles with random coordinates in [−1, 1]³ and RGBA colours on a
/// 1/255 grid (so 8-bit colour formats round-trip exactly); deterministic for a seed.
reduced::TriangleMesh random_soup(int count, std::uint32_t seed);

}  // namespace khz::test
