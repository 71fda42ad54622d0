#pragma once
// STereoLithography (STL) surface meshes, ASCII and binary.

#include <khz/reduced/export.hpp>
#include <khz/reduced/mesh/triangle_mesh.hpp>

#include <string>
#include <string_view>

namespace khz::reduced {

/// Parses ASCII or binary STL (detected from the content: a binary file's size is exactly
/// 84 + 50·n bytes, even when its header starts with "solid"). STL stores each triangle's
/// corners separately; corners with bit-identical coordinates are merged into one vertex so
/// the result has connectivity. Facet normals are ignored (they follow from the winding).
/// @throws ParseError naming source and line (ASCII) or byte offset (binary).
KHZ_REDUCED_API TriangleMesh parse_stl(std::string_view data, const std::string& source);

/// Binary STL bytes for `mesh` (single-precision coordinates, computed facet normals).
KHZ_REDUCED_API std::string format_stl_binary(const TriangleMesh& mesh);
/// ASCII STL text for `mesh` (coordinates printed to round-trip exactly).
KHZ_REDUCED_API std::string format_stl_ascii(const TriangleMesh& mesh);

}  // namespace khz::reduced
