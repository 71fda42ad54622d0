#pragma once
// Gmsh MSH 2.2 ASCII volumetric meshes.

#include <khz/reduced/export.hpp>
#include <khz/reduced/mesh/volume_mesh.hpp>

#include <string>
#include <string_view>

namespace khz::reduced {

/// Parses an MSH 2.2 ASCII file: $MeshFormat, $Nodes, $Elements (other sections skipped).
/// Keeps the volume elements — 4-node tetrahedra (type 4) or 8-node hexahedra (type 5) — and
/// drops points, lines, triangles and quads (boundary entities). The first tag (physical
/// group) of each kept element becomes its element_groups entry. Node tags may be any
/// positive integers. A file mixing tetrahedra and hexahedra, or with no volume elements, is
/// rejected.
/// @throws ParseError naming the source and line.
KHZ_REDUCED_API VolumeMesh parse_gmsh(std::string_view data, const std::string& source);

/// MSH 2.2 ASCII text for `mesh` (element_groups written as physical and elementary tags).
KHZ_REDUCED_API std::string format_gmsh(const VolumeMesh& mesh);

}  // namespace khz::reduced
