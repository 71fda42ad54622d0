#pragma once
// TetGen .node/.ele tetrahedral meshes.

#include <khz/reduced/export.hpp>
#include <khz/reduced/mesh/volume_mesh.hpp>

#include <string>
#include <string_view>

namespace khz::reduced {

/// A TetGen mesh as the text of its two files.
struct TetgenFiles {
  std::string node;  ///< Content of the .node file.
  std::string ele;   ///< Content of the .ele file.
};

/// Parses a TetGen mesh from its .node text (`#points 3 #attributes boundary-marker?`, then one
/// line per point; 0- or 1-based numbering, detected from the first point) and .ele text
/// (`#tets nodes-per-tet(4 or 10) #attributes`, then one line per tet). Only the 4 corner
/// nodes of 10-node tets are kept; the first region attribute, when present, becomes
/// element_groups. `#` starts a comment.
/// @throws ParseError naming the file and line.
KHZ_REDUCED_API VolumeMesh parse_tetgen(std::string_view node_data, const std::string& node_source,
                                        std::string_view ele_data, const std::string& ele_source);

/// TetGen text for a tetrahedral mesh (1-based numbering, element_groups as a region
/// attribute when present). @throws MeshError for a hexahedral mesh.
KHZ_REDUCED_API TetgenFiles format_tetgen(const VolumeMesh& mesh);

}  // namespace khz::reduced
