#pragma once
// Pieces shared by the TetGen and Gmsh readers and writers: row checks, mesh assembly and
// shortest round-trip number text (which the VTK writers use too).

#include <khz/reduced/mesh/volume_mesh.hpp>

#include "detail/number_text.hpp"
#include "detail/text_scanner.hpp"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace khz::reduced::detail {

/// Number of whitespace-separated fields in `rest` before the first one starting with `comment`.
/// Rows are counted before they are parsed so a short or long row gets one clear message.
inline std::int64_t count_fields(std::string_view rest, char comment) {
  // A scanner over the single line splits tokens exactly as the caller's scanner will.
  TextScanner fields(rest, std::string());
  fields.next_line();
  std::int64_t count = 0;
  for (std::string_view token = fields.next_token(); !token.empty() && token.front() != comment;
       token = fields.next_token()) {
    ++count;
  }
  return count;
}

/// Vertices, element nodes and groups collected row by row while parsing.
struct VolumeMeshRows {
  std::vector<double> coordinates;  ///< x y z per vertex.
  std::vector<int> element_nodes;   ///< nodes_per_element(type) zero-based indices per element.
  std::vector<int> groups;          ///< Empty, or one group per element.

  VolumeMesh build(ElementType type) const {
    const auto width = static_cast<Eigen::Index>(nodes_per_element(type));
    VolumeMesh mesh;
    mesh.element_type = type;
    mesh.vertices = Eigen::Map<const VertexMatrix>(
        coordinates.data(), static_cast<Eigen::Index>(coordinates.size()) / 3, 3);
    mesh.elements = Eigen::Map<const ElementMatrix>(
        element_nodes.data(), static_cast<Eigen::Index>(element_nodes.size()) / width, width);
    if (!groups.empty()) {
      mesh.element_groups = Eigen::Map<const Eigen::VectorXi>(
          groups.data(), static_cast<Eigen::Index>(groups.size()));
    }
    return mesh;
  }
};

/// Fails through `at` (a TextScanner, or anything with fail()) unless the last `width` entries
/// of `element_nodes` (the element just read) are distinct: such an element has no volume and
/// validate() rejects it. `noun` and `number` name it in the file's terms, e.g. "element" 7.
template <typename Reporter>
void check_distinct_nodes(const Reporter& at, const std::vector<int>& element_nodes, int width,
                          std::string_view noun, std::int64_t number) {
  const int* nodes = element_nodes.data() + element_nodes.size() - width;
  for (int a = 0; a < width; ++a) {
    for (int b = a + 1; b < width; ++b) {
      if (nodes[a] == nodes[b]) {
        at.fail(std::string(noun) + " " + std::to_string(number) +
                " lists one node twice (as corners " + std::to_string(a + 1) + " and " +
                std::to_string(b + 1) + ")");
      }
    }
  }
}

/// Appends one "index x y z" line per vertex, numbered from 1: the node block of both a TetGen
/// .node file and an MSH $Nodes section.
inline void append_numbered_vertices(std::string& out, const VertexMatrix& vertices) {
  for (Eigen::Index v = 0; v < vertices.rows(); ++v) {
    append_number<std::int64_t>(out, v + 1);
    for (Eigen::Index axis = 0; axis < 3; ++axis) {
      out += ' ';
      append_number(out, vertices(v, axis));
    }
    out += '\n';
  }
}

}  // namespace khz::reduced::detail
