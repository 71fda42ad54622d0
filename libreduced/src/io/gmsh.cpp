#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/gmsh.hpp>

#include "detail/text_scanner.hpp"
#include "io/gmsh_parsing.hpp"
#include "io/msh_input.hpp"
#include "io/volume_parsing.hpp"

#include <cstdint>
#include <string>
#include <string_view>

namespace khz::reduced {
namespace {

using detail::GmshTags;
using detail::MshTextInput;
using detail::TextScanner;

using detail::any_integer_max;
using detail::any_integer_min;
using detail::max_index;
using detail::no_comment;  // MSH has no comment syntax
// The shortest node or element row, e.g. "1 0 0 0", plus its line break.
constexpr std::size_t min_row_bytes = 8;

GmshTags read_nodes(MshTextInput& in, detail::VolumeMeshRows& rows) {
  TextScanner& s = in.scanner();
  s.require_content_line(no_comment, "the node count");
  const std::int64_t count = s.require_integer("node count", 0, max_index);
  detail::check_count_fits(s, count, min_row_bytes, "nodes");
  GmshTags tags;
  tags.reserve(static_cast<std::size_t>(count));
  rows.coordinates.reserve(static_cast<std::size_t>(3 * count));
  for (std::int64_t row = 0; row < count; ++row) {
    s.require_row(no_comment, "node", row, count);
    const std::int64_t found = detail::count_fields(s.rest_of_line(), no_comment);
    if (found != 4) {
      s.fail("node row has " + std::to_string(found) + " values, expected 4: tag, x, y, z");
    }
    tags.add(s.require_integer("node tag", 1, any_integer_max), static_cast<int>(row));
    rows.coordinates.push_back(s.require_double("x coordinate"));
    rows.coordinates.push_back(s.require_double("y coordinate"));
    rows.coordinates.push_back(s.require_double("z coordinate"));
  }
  detail::expect_gmsh_marker(in, "$EndNodes",
                             " after the " + std::to_string(count) + " nodes the header declares");
  if (const auto twin = tags.seal()) {
    s.fail("node tag " + std::to_string(*twin) + " is defined twice in $Nodes");
  }
  return tags;
}

/// Reads $Elements, keeping the volume elements; returns their type.
ElementType read_elements(MshTextInput& in, const GmshTags& tags, detail::VolumeMeshRows& rows) {
  TextScanner& s = in.scanner();
  s.require_content_line(no_comment, "the element count");
  const std::int64_t count = s.require_integer("element count", 0, any_integer_max);
  detail::check_count_fits(s, count, min_row_bytes, "elements");
  const detail::GmshElementKind* volume = nullptr;  // kind of the kept elements, once one is seen
  bool tagged = false;                              // whether any kept element has a physical group
  for (std::int64_t row = 0; row < count; ++row) {
    s.require_row(no_comment, "element", row, count);
    const std::int64_t element = s.require_integer("element tag", any_integer_min, any_integer_max);
    const std::int64_t type = s.require_integer("element type", any_integer_min, any_integer_max);
    const detail::GmshElementKind& kind =
        detail::require_gmsh_kind(s, type, "element " + std::to_string(element));
    const std::int64_t tag_count = s.require_integer("tag count", 0, max_index);
    const std::int64_t values = detail::count_fields(s.rest_of_line(), no_comment);
    if (values < tag_count) {
      s.fail("element " + std::to_string(element) + " declares " + std::to_string(tag_count) +
             " tags but lists only " + std::to_string(values) + " values after them");
    }
    if (values - tag_count != kind.nodes) {
      s.fail("element " + std::to_string(element) + " has " + std::to_string(values - tag_count) +
             " nodes, but " + detail::describe(kind) + " has " + std::to_string(kind.nodes));
    }
    const bool keep = kind.role == detail::GmshRole::volume;
    if (keep) detail::check_one_volume_type(s, kind, volume);

    // The first tag is the physical group; the others (elementary entity, partitions) are unused.
    int group = 0;
    for (std::int64_t t = 0; t < tag_count; ++t) {
      if (t == 0 && keep) {
        group = static_cast<int>(s.require_integer("physical group", 0, max_index));
      } else {
        s.require_integer("element tag value", any_integer_min, any_integer_max);
      }
    }
    for (std::int64_t k = 0; k < kind.nodes; ++k) {
      const std::int64_t tag = s.require_integer("node tag", any_integer_min, any_integer_max);
      const auto vertex = tags.find(tag);
      if (!vertex) detail::fail_undefined_node(s, element, tag);
      if (keep) rows.element_nodes.push_back(*vertex);
    }
    if (keep) {
      detail::check_distinct_nodes(s, rows.element_nodes, static_cast<int>(kind.nodes), "element",
                                   element);
      volume = &kind;
      rows.groups.push_back(group);
      tagged = tagged || tag_count > 0;
    }
  }
  detail::expect_gmsh_marker(
      in, "$EndElements", " after the " + std::to_string(count) + " elements the header declares");
  if (volume == nullptr) s.fail("$Elements holds no tetrahedra or hexahedra");
  if (!tagged) rows.groups.clear();
  return volume->element_type;
}

/// The $Nodes and $Elements layout of MSH 2 (2.0, 2.1 and 2.2 share it): one row per node or
/// element, the element's tags (physical group first) inline.
struct Msh22 {
  GmshTags read_nodes(MshTextInput& in, detail::VolumeMeshRows& rows) const {
    return reduced::read_nodes(in, rows);
  }
  ElementType read_elements(MshTextInput& in, const GmshTags& tags,
                            detail::VolumeMeshRows& rows) const {
    return reduced::read_elements(in, tags, rows);
  }
  /// MSH 2 has no sections of its own beyond $Nodes and $Elements.
  bool read_section(MshTextInput&, std::string_view) const { return false; }
};

std::string format_msh22(const VolumeMesh& mesh) {
  std::string out = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n";
  detail::append_number<std::int64_t>(out, mesh.num_vertices());
  out += '\n';
  detail::append_numbered_vertices(out, mesh.vertices);
  out += "$EndNodes\n$Elements\n";
  detail::append_number<std::int64_t>(out, mesh.num_elements());
  out += '\n';
  const char* type = mesh.element_type == ElementType::tetrahedron ? " 4" : " 5";
  // Without groups no tags are written, so reading the file back gives no groups either.
  const bool grouped = mesh.element_groups.size() > 0;
  for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
    detail::append_number<std::int64_t>(out, e + 1);
    out += type;
    if (grouped) {
      // The group serves as both physical group and elementary entity.
      out += " 2 ";
      detail::append_number<std::int64_t>(out, mesh.element_groups[e]);
      out += ' ';
      detail::append_number<std::int64_t>(out, mesh.element_groups[e]);
    } else {
      out += " 0";
    }
    for (Eigen::Index k = 0; k < mesh.elements.cols(); ++k) {
      out += ' ';
      detail::append_number<std::int64_t>(out, mesh.elements(e, k) + 1);
    }
    out += '\n';
  }
  out += "$EndElements\n";
  return out;
}

}  // namespace

VolumeMesh parse_gmsh(std::string_view data, const std::string& source) {
  TextScanner s(data, source);
  MshTextInput text(s);
  detail::expect_gmsh_marker(text, "$MeshFormat");
  s.require_content_line(no_comment, "the MSH version line (e.g. 4.1 0 8)");
  const double version = s.require_double("MSH version");
  const std::int64_t file_type = s.require_integer("file type", any_integer_min, any_integer_max);
  const std::int64_t data_size = s.require_integer("data size", any_integer_min, any_integer_max);
  // 2.0 and 2.1 share 2.2's layout; 4.0 differs from 4.1 in most rows.
  const bool msh2 = version >= 2.0 && version < 3.0;
  if (!msh2 && version != 4.1) {
    s.fail("unsupported MSH version " + detail::number_text(version) + " (expected 2.2 or 4.1)");
  }
  if (file_type != 0 && file_type != 1) {
    s.fail("unknown MSH file-type " + std::to_string(file_type) +
           " (expected 0, ASCII, or 1, binary)");
  }
  if (msh2) {
    if (file_type == 1) {
      s.fail("binary MSH 2 (file-type 1) is not supported: save MSH 4.1 or MSH 2.2 ASCII");
    }
    detail::expect_gmsh_marker(text, "$EndMeshFormat");
    Msh22 format;
    return detail::read_gmsh_sections(text, format);
  }
  if (file_type == 0) {
    detail::expect_gmsh_marker(text, "$EndMeshFormat");
    return detail::parse_msh41(text);
  }
  if (data_size != 8) {
    s.fail("binary MSH with data size " + std::to_string(data_size) +
           " is not supported: size_t must take 8 bytes");
  }
  detail::MshBinaryInput binary(data, source, data.size() - s.remaining_bytes());
  binary.read_byte_order();
  detail::expect_gmsh_marker(binary, "$EndMeshFormat");
  return detail::parse_msh41(binary);
}

std::string format_gmsh(const VolumeMesh& mesh, GmshFormat format) {
  validate(mesh);  // the writers index element_groups by element
  switch (format) {
    case GmshFormat::msh41_ascii:
      return detail::format_msh41(mesh, false);
    case GmshFormat::msh41_binary:
      return detail::format_msh41(mesh, true);
    case GmshFormat::msh22_ascii:
      break;
  }
  return format_msh22(mesh);
}

}  // namespace khz::reduced
