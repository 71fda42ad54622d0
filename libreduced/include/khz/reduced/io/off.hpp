#pragma once
// Object File Format (OFF) surface meshes, including CGAL's coloured COFF variant.

#include <khz/reduced/export.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <string>
#include <string_view>

namespace khz::reduced {

/// Parses OFF text: header `OFF` (or `COFF`, `NOFF`, `CNOFF`: vertex colours and/or normals
/// follow each vertex), counts `V F E`, V vertex lines, F face lines `n i0 … i(n−1) [colour]`.
/// COFF colours may be integers in [0, 255] or floats in [0, 1], RGB or RGBA. Polygons are
/// split into triangle fans; per-face colours and normals are dropped. Counts are checked
/// against the file size before anything is allocated.
/// @param data   the file's bytes.
/// @param source name used in error messages (usually the path).
/// @throws ParseError naming source and line for malformed input.
KHZ_REDUCED_API TriangleMesh parse_off(std::string_view data, const std::string& source);

/// OFF text for `mesh`; `COFF` with 0–255 RGBA colours when the mesh has vertex colours.
KHZ_REDUCED_API std::string format_off(const TriangleMesh& mesh);

}  // namespace khz::reduced
