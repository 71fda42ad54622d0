#pragma once
// Wavefront OBJ surface meshes.

#include <khz/reduced/export.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <string>
#include <string_view>

namespace khz::reduced {

/// Parses OBJ text: `v x y z [r g b]` vertices (optional colours in [0, 1]) and `f` faces in
/// any of the forms `i`, `i/t`, `i//n`, `i/t/n`, with negative (relative) indices. Polygons
/// with more than three corners are split into a triangle fan from their first corner.
/// Texture coordinates, normals, groups, materials, lines and points are ignored.
/// @param data   the file's bytes.
/// @param source name used in error messages (usually the path).
/// @throws ParseError naming source and line for malformed input or out-of-range indices.
KHZ_REDUCED_API TriangleMesh parse_obj(std::string_view data, const std::string& source);

/// OBJ text for `mesh` (vertex colours written as `v x y z r g b` when present), with
/// coordinates printed to round-trip exactly.
KHZ_REDUCED_API std::string format_obj(const TriangleMesh& mesh);

}  // namespace khz::reduced
