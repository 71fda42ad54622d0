#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/gmsh.hpp>

#include "detail/text_scanner.hpp"
#include "io/volume_parsing.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace khz::reduced {
namespace {

using detail::TextScanner;

using detail::any_integer_max;
using detail::any_integer_min;
using detail::max_index;
using detail::no_comment;  // MSH has no comment syntax
// The shortest node or element row, e.g. "1 0 0 0", plus its line break.
constexpr std::size_t min_row_bytes = 8;

/// What the reader does with an element type.
enum class Role {
  boundary,     // points, lines, faces: dropped
  volume,       // kept
  unsupported,  // other volume elements: rejected
};

struct ElementKind {
  std::int64_t type;
  std::int64_t nodes;
  const char* name;
  Role role;
  ElementType element_type;  // meaningful for Role::volume only
};

constexpr ElementKind element_kinds[] = {
    {15, 1, "point", Role::boundary, {}},
    {1, 2, "line", Role::boundary, {}},
    {8, 3, "3-node line", Role::boundary, {}},
    {2, 3, "triangle", Role::boundary, {}},
    {9, 6, "6-node triangle", Role::boundary, {}},
    {3, 4, "quadrangle", Role::boundary, {}},
    {4, 4, "tetrahedron", Role::volume, ElementType::tetrahedron},
    {5, 8, "hexahedron", Role::volume, ElementType::hexahedron},
    {6, 6, "prism", Role::unsupported, {}},
    {7, 5, "pyramid", Role::unsupported, {}},
    {11, 10, "10-node tetrahedron", Role::unsupported, {}},
    {12, 27, "27-node hexahedron", Role::unsupported, {}},
    {17, 20, "20-node hexahedron", Role::unsupported, {}},
};

const ElementKind* find_kind(std::int64_t type) {
  for (const ElementKind& kind : element_kinds) {
    if (kind.type == type) return &kind;
  }
  return nullptr;
}

std::string describe(const ElementKind& kind) {
  return "type " + std::to_string(kind.type) + " (" + kind.name + ")";
}

/// True for a well-formed section marker such as "$Nodes", which is then safe to quote.
bool is_marker(std::string_view token) {
  constexpr std::size_t max_length = 40;
  if (token.size() < 2 || token.size() > max_length || token.front() != '$') return false;
  return std::all_of(token.begin() + 1, token.end(),
                     [](unsigned char c) { return std::isalnum(c) != 0 || c == '_'; });
}

std::string describe_line(std::string_view first_token) {
  return is_marker(first_token) ? std::string(first_token) : "a line that is not a section marker";
}

/// Moves to the next line, which must be the section marker `marker`; `context` (e.g. " after
/// the 8 nodes the header declares") explains a mismatch.
void expect_marker(TextScanner& s, std::string_view marker, const std::string& context = {}) {
  s.require_content_line(no_comment, marker);
  const std::string_view token = s.next_token();
  if (token != marker) {
    s.fail("expected " + std::string(marker) + context + ", found " + describe_line(token));
  }
}

void read_mesh_format(TextScanner& s) {
  expect_marker(s, "$MeshFormat");
  s.require_content_line(no_comment, "the MSH version line (2.2 0 8)");
  const double version = s.require_double("MSH version");
  // 2.0 and 2.1 share 2.2's $Nodes and $Elements layout.
  if (version < 2.0 || version >= 3.0) {
    std::string text;
    detail::append_number(text, version);
    s.fail("unsupported MSH version " + text + " (expected 2.2 ASCII)");
  }
  const std::int64_t file_type = s.require_integer("file type", any_integer_min, any_integer_max);
  if (file_type == 1) {
    s.fail("binary MSH (file-type 1) is not supported: only ASCII (file-type 0) is");
  }
  if (file_type != 0) {
    s.fail("unknown MSH file-type " + std::to_string(file_type) + " (expected 0, ASCII)");
  }
  s.require_integer("data size", any_integer_min, any_integer_max);  // only binary files use it
  expect_marker(s, "$EndMeshFormat");
}

/// MSH node tags, which may be any positive integers, and the 0-based vertex each one names
/// (vertices keep the file's order). A sorted vector rather than a table indexed by tag, so a
/// huge tag costs nothing, and rather than a hash map, so crafted tags cannot force collisions.
class NodeTags {
 public:
  void reserve(std::size_t count) { m_entries.reserve(count); }
  void add(std::int64_t tag) { m_entries.emplace_back(tag, static_cast<int>(m_entries.size())); }

  /// Sorts the tags; returns a tag defined twice, if any.
  std::optional<std::int64_t> seal() {
    std::sort(m_entries.begin(), m_entries.end());
    const auto twin =
        std::adjacent_find(m_entries.begin(), m_entries.end(),
                           [](const auto& a, const auto& b) { return a.first == b.first; });
    if (twin == m_entries.end()) return std::nullopt;
    return twin->first;
  }

  /// The vertex with `tag`, or -1.
  int find(std::int64_t tag) const {
    const auto it = std::lower_bound(m_entries.begin(), m_entries.end(), std::make_pair(tag, 0));
    return it != m_entries.end() && it->first == tag ? it->second : -1;
  }

 private:
  std::vector<std::pair<std::int64_t, int>> m_entries;
};

NodeTags read_nodes(TextScanner& s, detail::VolumeMeshRows& rows) {
  s.require_content_line(no_comment, "the node count");
  const std::int64_t count = s.require_integer("node count", 0, max_index);
  detail::check_count_fits(s, count, min_row_bytes, "nodes");
  NodeTags tags;
  tags.reserve(static_cast<std::size_t>(count));
  rows.coordinates.reserve(static_cast<std::size_t>(3 * count));
  for (std::int64_t row = 0; row < count; ++row) {
    s.require_row(no_comment, "node", row, count);
    const std::int64_t found = detail::count_fields(s.rest_of_line(), no_comment);
    if (found != 4) {
      s.fail("node row has " + std::to_string(found) + " values, expected 4: tag, x, y, z");
    }
    tags.add(s.require_integer("node tag", 1, any_integer_max));
    rows.coordinates.push_back(s.require_double("x coordinate"));
    rows.coordinates.push_back(s.require_double("y coordinate"));
    rows.coordinates.push_back(s.require_double("z coordinate"));
  }
  expect_marker(s, "$EndNodes",
                " after the " + std::to_string(count) + " nodes the header declares");
  if (const auto twin = tags.seal()) {
    s.fail("node tag " + std::to_string(*twin) + " is defined twice in $Nodes");
  }
  return tags;
}

/// Reads the element type and checks it can be read; returns its description.
const ElementKind& read_kind(TextScanner& s, std::int64_t element) {
  const std::int64_t type = s.require_integer("element type", any_integer_min, any_integer_max);
  const ElementKind* kind = find_kind(type);
  if (kind == nullptr) {
    s.fail("element " + std::to_string(element) + " has unsupported type " + std::to_string(type));
  }
  if (kind->role == Role::unsupported) {
    s.fail("element " + std::to_string(element) + " has " + describe(*kind) +
           "; only linear tetrahedra (type 4) and hexahedra (type 5) are supported");
  }
  return *kind;
}

/// Reads $Elements, keeping the volume elements; returns their type.
ElementType read_elements(TextScanner& s, const NodeTags& tags, detail::VolumeMeshRows& rows) {
  s.require_content_line(no_comment, "the element count");
  const std::int64_t count = s.require_integer("element count", 0, any_integer_max);
  detail::check_count_fits(s, count, min_row_bytes, "elements");
  const ElementKind* volume = nullptr;  // kind of the kept elements, once one is seen
  bool tagged = false;                  // whether any kept element has a physical group
  for (std::int64_t row = 0; row < count; ++row) {
    s.require_row(no_comment, "element", row, count);
    const std::int64_t element = s.require_integer("element tag", any_integer_min, any_integer_max);
    const ElementKind& kind = read_kind(s, element);
    const std::int64_t tag_count = s.require_integer("tag count", 0, max_index);
    const std::int64_t values = detail::count_fields(s.rest_of_line(), no_comment);
    if (values < tag_count) {
      s.fail("element " + std::to_string(element) + " declares " + std::to_string(tag_count) +
             " tags but lists only " + std::to_string(values) + " values after them");
    }
    if (values - tag_count != kind.nodes) {
      s.fail("element " + std::to_string(element) + " has " + std::to_string(values - tag_count) +
             " nodes, but " + describe(kind) + " has " + std::to_string(kind.nodes));
    }
    const bool keep = kind.role == Role::volume;
    if (keep && volume != nullptr && volume != &kind) {
      s.fail("element " + describe(kind) + " mixed with " + describe(*volume) +
             ": a mesh has one element type");
    }

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
      const int vertex = tags.find(tag);
      if (vertex < 0) {
        s.fail("element " + std::to_string(element) + " uses node tag " + std::to_string(tag) +
               ", which $Nodes does not define");
      }
      if (keep) rows.element_nodes.push_back(vertex);
    }
    if (keep) {
      detail::check_distinct_nodes(s, rows.element_nodes, static_cast<int>(kind.nodes),
                                   "element " + std::to_string(element));
      volume = &kind;
      rows.groups.push_back(group);
      tagged = tagged || tag_count > 0;
    }
  }
  expect_marker(s, "$EndElements",
                " after the " + std::to_string(count) + " elements the header declares");
  if (volume == nullptr) s.fail("$Elements holds no tetrahedra or hexahedra");
  if (!tagged) rows.groups.clear();
  return volume->element_type;
}

/// Skips a section the reader does not use, such as $PhysicalNames or $NodeData.
void skip_section(TextScanner& s, std::string_view marker) {
  const std::string end = "$End" + std::string(marker.substr(1));
  do {
    s.require_content_line(no_comment, end);
  } while (s.next_token() != end);
}

}  // namespace

VolumeMesh parse_gmsh(std::string_view data, const std::string& source) {
  TextScanner s(data, source);
  read_mesh_format(s);
  detail::VolumeMeshRows rows;
  std::optional<NodeTags> tags;
  std::optional<ElementType> type;
  while (s.next_content_line(no_comment)) {
    const std::string_view token = s.next_token();
    if (token == "$Nodes") {
      if (tags) s.fail("second $Nodes section; one is supported");
      tags = read_nodes(s, rows);
    } else if (token == "$Elements") {
      if (!tags) s.fail("$Elements comes before $Nodes");
      if (type) s.fail("second $Elements section; one is supported");
      type = read_elements(s, *tags, rows);
    } else if (is_marker(token) && !token.starts_with("$End")) {
      skip_section(s, token);
    } else {
      s.fail("expected a section such as $Nodes or $Elements, found " + describe_line(token));
    }
  }
  if (!tags) s.fail("file ends without a $Nodes section");
  if (!type) s.fail("file ends without an $Elements section");
  return rows.build(*type);
}

std::string format_gmsh(const VolumeMesh& mesh) {
  validate(mesh);  // the rows below index element_groups by element
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

}  // namespace khz::reduced
