#include <khz/reduced/errors.hpp>
#include <khz/reduced/io/tetgen.hpp>

#include "detail/text_scanner.hpp"
#include "io/volume_parsing.hpp"

#include <cmath>
#include <cstdint>
#include <string>

namespace khz::reduced {
namespace {

using detail::TextScanner;

constexpr char comment = '#';
using detail::any_integer_max;
using detail::any_integer_min;
using detail::max_index;

std::string count_of(std::int64_t count, const char* noun) {
  return std::to_string(count) + " " + noun + (count == 1 ? "" : "s");
}

/// The rows of a .node or .ele file. TetGen numbers them consecutively from 0 or 1; the first
/// row fixes which.
struct RowList {
  std::string kind;         // "node" or "tetrahedron"
  std::string index_name;   // kind + " index", built once rather than per row
  std::int64_t count = 0;   // rows the header declares
  std::int64_t fields = 0;  // values per row, index included
  std::string layout;       // the values a row holds, for error messages
  std::int64_t base = 0;    // index of the first row
};

/// Moves to row `row` of `list`, checks its value count and index, and returns the index.
std::int64_t start_row(TextScanner& s, RowList& list, std::int64_t row) {
  s.require_row(comment, list.kind, row, list.count);
  const std::int64_t found = detail::count_fields(s.rest_of_line(), comment);
  if (found != list.fields) {
    s.fail(list.kind + " row has " + count_of(found, "value") + ", expected " +
           std::to_string(list.fields) + ": " + list.layout);
  }
  const std::int64_t index = s.require_integer(list.index_name, any_integer_min, any_integer_max);
  if (row == 0) {
    if (index != 0 && index != 1) {
      s.fail("first " + list.kind + " index is " + std::to_string(index) +
             "; TetGen numbering starts at 0 or 1");
    }
    list.base = index;
  } else if (index != list.base + row) {
    s.fail(list.kind + " index " + std::to_string(index) +
           " breaks consecutive numbering: expected " + std::to_string(list.base + row));
  }
  return index;
}

/// Rejects content after the declared rows: it means the header count is wrong.
void require_end(TextScanner& s, const RowList& list) {
  if (s.next_content_line(comment)) {
    s.fail("more " + list.kind + " rows follow than the " + std::to_string(list.count) +
           " the header declares");
  }
}

/// Reads the header count of a list; zero rows is an error, since the mesh would be empty.
std::int64_t read_count(TextScanner& s, const char* what, const char* empty_message) {
  const std::int64_t count = s.require_integer(what, 0, max_index);
  if (count == 0) s.fail(empty_message);
  return count;
}

/// Values per row after the index, e.g. ", 2 attributes, boundary marker".
std::string attribute_layout(std::int64_t attributes, bool marker) {
  std::string layout;
  if (attributes > 0) layout += ", " + count_of(attributes, "attribute");
  if (marker) layout += ", boundary marker";
  return layout;
}

RowList read_nodes(TextScanner& s, detail::VolumeMeshRows& rows) {
  s.require_content_line(comment,
                         "the .node header: node count, dimension, attribute count, marker flag");
  RowList list;
  list.kind = "node";
  list.index_name = "node index";
  list.count = read_count(s, "node count", "the .node file declares no nodes");
  const std::int64_t dimension = s.require_integer("dimension", any_integer_min, any_integer_max);
  if (dimension != 3) {
    s.fail("dimension " + std::to_string(dimension) + " is not supported: expected 3");
  }
  const std::int64_t attributes = s.require_integer("attribute count", 0, max_index);
  const bool marker = s.require_integer("boundary-marker flag", 0, 1) == 1;
  list.fields = 4 + attributes + (marker ? 1 : 0);
  list.layout = "index, x, y, z" + attribute_layout(attributes, marker);
  // Each value takes at least one character and one separator.
  detail::check_count_fits(s, list.count, static_cast<std::size_t>(2 * list.fields - 1), "nodes");

  rows.coordinates.reserve(static_cast<std::size_t>(3 * list.count));
  for (std::int64_t row = 0; row < list.count; ++row) {
    start_row(s, list, row);
    rows.coordinates.push_back(s.require_double("x coordinate"));
    rows.coordinates.push_back(s.require_double("y coordinate"));
    rows.coordinates.push_back(s.require_double("z coordinate"));
    for (std::int64_t a = 0; a < attributes; ++a) s.require_double("node attribute");
    if (marker) s.require_integer("boundary marker", any_integer_min, any_integer_max);
  }
  require_end(s, list);
  return list;
}

/// Reads a region attribute, which TetGen stores as a real number, as a group id.
int read_group(TextScanner& s, std::int64_t tetrahedron) {
  const double value = s.require_double("region attribute");
  if (value < 0.0 || value > static_cast<double>(max_index) || std::floor(value) != value) {
    std::string text;
    detail::append_number(text, value);
    s.fail("tetrahedron " + std::to_string(tetrahedron) + " has region attribute " + text +
           "; expected a non-negative integer");
  }
  return static_cast<int>(value);
}

void read_tetrahedra(TextScanner& s, const RowList& nodes, const std::string& node_source,
                     detail::VolumeMeshRows& rows) {
  s.require_content_line(comment,
                         "the .ele header: tetrahedron count, nodes per tetrahedron, "
                         "attribute count");
  RowList list;
  list.kind = "tetrahedron";
  list.index_name = "tetrahedron index";
  list.count = read_count(s, "tetrahedron count", "the .ele file declares no tetrahedra");
  const std::int64_t width =
      s.require_integer("nodes per tetrahedron", any_integer_min, any_integer_max);
  if (width != 4 && width != 10) {
    s.fail("nodes per tetrahedron must be 4 or 10, found " + std::to_string(width));
  }
  const std::int64_t attributes = s.require_integer("attribute count", 0, max_index);
  list.fields = 1 + width + attributes;
  list.layout = "index, " + std::to_string(width) + " nodes" + attribute_layout(attributes, false);
  detail::check_count_fits(s, list.count, static_cast<std::size_t>(2 * list.fields - 1),
                           "tetrahedra");

  const std::int64_t first = nodes.base;
  const std::int64_t last = nodes.base + nodes.count - 1;
  rows.element_nodes.reserve(static_cast<std::size_t>(4 * list.count));
  if (attributes > 0) rows.groups.reserve(static_cast<std::size_t>(list.count));
  for (std::int64_t row = 0; row < list.count; ++row) {
    const std::int64_t index = start_row(s, list, row);
    for (std::int64_t k = 0; k < width; ++k) {
      const std::int64_t node = s.require_integer("node index", any_integer_min, any_integer_max);
      if (node < first || node > last) {
        s.fail("tetrahedron " + std::to_string(index) + " uses node " + std::to_string(node) +
               ", but " + node_source + " defines nodes " + std::to_string(first) + ".." +
               std::to_string(last));
      }
      // A 10-node tetrahedron lists its 4 corners first; the edge midpoints are dropped.
      if (k < 4) rows.element_nodes.push_back(static_cast<int>(node - first));
    }
    detail::check_distinct_nodes(s, rows.element_nodes, 4, "tetrahedron", index);
    if (attributes > 0) rows.groups.push_back(read_group(s, index));
    for (std::int64_t a = 1; a < attributes; ++a) s.require_double("tetrahedron attribute");
  }
  require_end(s, list);
}

}  // namespace

VolumeMesh parse_tetgen(std::string_view node_data, const std::string& node_source,
                        std::string_view ele_data, const std::string& ele_source) {
  detail::VolumeMeshRows rows;
  TextScanner node_scanner(node_data, node_source);
  const RowList nodes = read_nodes(node_scanner, rows);
  TextScanner ele_scanner(ele_data, ele_source);
  read_tetrahedra(ele_scanner, nodes, node_source, rows);
  return rows.build(ElementType::tetrahedron);
}

TetgenFiles format_tetgen(const VolumeMesh& mesh) {
  if (mesh.element_type != ElementType::tetrahedron) {
    throw MeshError("TetGen files hold tetrahedra only; this mesh has hexahedra");
  }
  validate(mesh);  // the rows below index element_groups by element
  const bool grouped = mesh.element_groups.size() > 0;

  TetgenFiles files;
  detail::append_number<std::int64_t>(files.node, mesh.num_vertices());
  files.node += " 3 0 0\n";
  detail::append_numbered_vertices(files.node, mesh.vertices);

  detail::append_number<std::int64_t>(files.ele, mesh.num_elements());
  files.ele += grouped ? " 4 1\n" : " 4 0\n";
  for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
    detail::append_number<std::int64_t>(files.ele, e + 1);
    for (Eigen::Index k = 0; k < 4; ++k) {
      files.ele += ' ';
      detail::append_number<std::int64_t>(files.ele, mesh.elements(e, k) + 1);
    }
    if (grouped) {
      files.ele += ' ';
      detail::append_number<std::int64_t>(files.ele, mesh.element_groups[e]);
    }
    files.ele += '\n';
  }
  return files;
}

}  // namespace khz::reduced
