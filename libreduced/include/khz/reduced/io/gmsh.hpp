#pragma once
// Gmsh MSH volumetric meshes: MSH 2.2 ASCII, MSH 4.1 ASCII and binary.

#include <khz/reduced/export.hpp>
#include <khz/reduced/mesh/volume_mesh.hpp>

#include <string>
#include <string_view>

namespace khz::reduced {

/// Parses an MSH file of one of these versions, as `$MeshFormat` declares it:
/// - 2.2 ASCII (also 2.0, 2.1): `$Nodes`, `$Elements` with one row per node or element. The
///   first tag (physical group) of each kept element becomes its element_groups entry; no
///   element with tags gives no groups.
/// - 4.1 ASCII and binary (`4.1 0 8`, `4.1 1 8`; what Gmsh 4 writes by default): `$Entities`
///   (optional), `$Nodes` and `$Elements` in entity blocks; nodes may carry parametric
///   coordinates, which are skipped. Binary files need data size 8 (size_t, as Gmsh writes on
///   64-bit systems) and may be either byte order (the endianness check int says which). Each
///   kept element's group is the first physical tag of its volume entity in `$Entities`, 0 for
///   a volume with none; no volume with a physical tag (or no `$Entities`) gives no groups.
///   Files with `$PartitionedEntities` are rejected: save them unpartitioned.
/// Sections other than these (`$PhysicalNames`, `$Periodic`, `$NodeData`, ...) are skipped.
/// Volume elements are kept — 4-node tetrahedra (type 4) or 8-node hexahedra (type 5) — and
/// points, lines, triangles and quadrangles (boundary entities) dropped. Vertices are all nodes
/// in file order; node tags may be any positive integers. Rejected: a file mixing tetrahedra and
/// hexahedra, one with no volume elements, other volume elements (second-order ones with a hint
/// to export linear elements, `gmsh -order 1`), MSH 2 binary and other versions.
/// @throws ParseError naming the source and the line (ASCII) or byte offset (binary data).
KHZ_REDUCED_API VolumeMesh parse_gmsh(std::string_view data, const std::string& source);

/// MSH versions and encodings format_gmsh() writes.
enum class GmshFormat {
  msh22_ascii,   ///< MSH 2.2 ASCII: groups as physical and elementary tags of each element.
  msh41_ascii,   ///< MSH 4.1 ASCII (Gmsh's `-format msh41`).
  msh41_binary,  ///< MSH 4.1 binary (`-format msh41 -bin`), little-endian.
};

/// MSH text or bytes for `mesh`; nodes and elements are tagged 1, 2, ... in order and
/// coordinates read back bit-exactly. In MSH 4.1 all nodes form one block of volume entity 1,
/// and each distinct element group is a volume entity (tags 1, 2, ... by increasing group)
/// whose one physical tag is the group; a mesh without groups has one volume entity with no
/// physical tag. Elements are written in order, one block per run of equal groups. Reading any
/// of these back with parse_gmsh() gives `mesh` again.
/// @throws MeshError if the mesh fails validate().
KHZ_REDUCED_API std::string format_gmsh(const VolumeMesh& mesh,
                                        GmshFormat format = GmshFormat::msh22_ascii);

}  // namespace khz::reduced
