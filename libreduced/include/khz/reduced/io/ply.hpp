#pragma once
// Polygon File Format (PLY) surface meshes: ASCII, binary little- and big-endian.

#include <khz/reduced/export.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <string>
#include <string_view>

namespace khz::reduced {

/// Parses PLY in any of its three encodings. Reads the `vertex` element's x, y, z and optional
/// red, green, blue, alpha (integer types scaled from [0, 255], float types taken as [0, 1]),
/// and the `face` element's `vertex_indices` (or `vertex_index`) list; polygons become
/// triangle fans. Every other element and property is skipped according to its declared type.
/// Element counts are checked against the file size before anything is allocated.
/// @throws ParseError naming source and line (header, ASCII body) or byte offset (binary body).
KHZ_REDUCED_API TriangleMesh parse_ply(std::string_view data, const std::string& source);

/// PLY encodings format_ply() can write.
enum class PlyEncoding { ascii, binary_little_endian, binary_big_endian };

/// PLY bytes for `mesh`: double coordinates, uchar RGBA when the mesh has colours, int indices.
KHZ_REDUCED_API std::string format_ply(const TriangleMesh& mesh,
                                       PlyEncoding encoding = PlyEncoding::binary_little_endian);

}  // namespace khz::reduced
