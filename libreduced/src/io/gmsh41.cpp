// MSH 4.1, ASCII and binary: the reader is written once against MshTextInput / MshBinaryInput,
// the writer once against a text or binary value sink.
#include <khz/reduced/errors.hpp>

#include "detail/number_text.hpp"
#include "io/gmsh_parsing.hpp"
#include "io/msh_input.hpp"
#include "io/volume_parsing.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace khz::reduced::detail {
namespace {

// MSH 4.1 writes entity tags, dimensions and element types as int.
constexpr std::int64_t int_min = std::numeric_limits<std::int32_t>::min();
constexpr std::int64_t int_max = std::numeric_limits<std::int32_t>::max();

constexpr const char* entity_kinds[4] = {"point entity", "curve entity", "surface entity",
                                         "volume entity"};

/// Reads the four size_t values of a $Nodes or $Elements header row: block count, item count
/// (at most `max`), smallest and largest tag (unused). Checks that the block headers and the
/// items (`item_bytes` each at least) fit in the file; returns block and item count.
template <typename Input>
std::pair<std::int64_t, std::int64_t> read_block_header(Input& in, const char* section,
                                                        const char* items, std::int64_t max,
                                                        std::size_t item_bytes) {
  const std::string row = "the " + std::string(section) + " header";
  in.begin_row(row);
  const std::int64_t blocks = in.size("entity block count", 0, any_integer_max);
  in.check_count_fits(blocks, 3 * Input::integer_bytes + Input::size_bytes, "entity blocks");
  const std::int64_t count = in.size(std::string(items) + " count", 0, max);
  in.check_count_fits(count, item_bytes, items);
  in.size("smallest tag", 0, any_integer_max);
  in.size("largest tag", 0, any_integer_max);
  in.end_row(row);
  return {blocks, count};
}

/// Fails unless a block of `in_block` items keeps the running total within the header's count.
template <typename Input>
void check_block_count(const Input& in, const char* block, std::int64_t index,
                       std::int64_t in_block, std::int64_t read, std::int64_t count,
                       const char* items, const char* section) {
  if (in_block > count - read) {
    in.fail(std::string(block) + " " + std::to_string(index + 1) + " holds " +
            std::to_string(in_block) + " " + items + ", more than the " +
            std::to_string(count - read) + " left of the " + std::to_string(count) + " the " +
            section + " header declares");
  }
}

/// Fails, at the section's end marker, if its blocks held fewer items than its header declares.
template <typename Input>
void check_total(const Input& in, std::int64_t read, std::int64_t count, const char* items,
                 const char* section) {
  if (read != count) {
    in.fail("the blocks hold " + std::to_string(read) + " " + items + ", but the " + section +
            " header declares " + std::to_string(count));
  }
}

/// The $Nodes, $Elements and $Entities layout of MSH 4.1.
struct Msh41 {
  /// Volume entity tag → its first physical tag, or -1; empty until $Entities is read.
  std::optional<GmshTags> volumes;
  bool elements_read = false;

  /// Reads $Entities (keeping each volume's first physical tag) or refuses
  /// $PartitionedEntities; false for other sections.
  template <typename Input>
  bool read_section(Input& in, std::string_view marker) {
    if (marker == "$PartitionedEntities") {
      in.fail(
          "partitioned meshes ($PartitionedEntities) are not supported: save the mesh "
          "unpartitioned");
    }
    if (marker != "$Entities") return false;
    if (volumes) in.fail("second $Entities section; one is supported");
    if (elements_read) in.fail("$Entities comes after $Elements");
    volumes = read_entities(in);
    return true;
  }

  template <typename Input>
  static GmshTags read_entities(Input& in) {
    const std::string header = "the $Entities header";
    in.begin_row(header);
    std::int64_t counts[4];
    for (std::int64_t& count : counts) count = in.size("entity count", 0, any_integer_max);
    in.end_row(header);
    GmshTags groups;
    for (int dim = 0; dim < 4; ++dim) {
      // Tag, bounding box (a point for points), physical tag count, bounding entity count.
      const int box = dim == 0 ? 3 : 6;
      const std::size_t min_bytes =
          Input::integer_bytes + box * Input::real_bytes + (dim == 0 ? 1 : 2) * Input::size_bytes;
      in.check_count_fits(counts[dim], min_bytes, std::string(entity_kinds[dim]) + "s");
      const std::string row = std::string("a ") + entity_kinds[dim] + " row";
      for (std::int64_t e = 0; e < counts[dim]; ++e) {
        in.begin_row(entity_kinds[dim], e, counts[dim]);
        const std::int64_t tag = in.integer("entity tag", int_min, int_max);
        for (int k = 0; k < box; ++k) in.skip_real("bounding box coordinate");
        const std::int64_t physicals = in.size("physical tag count", 0, any_integer_max);
        in.check_count_fits(physicals, Input::integer_bytes, "physical tags");
        int group = -1;
        for (std::int64_t p = 0; p < physicals; ++p) {
          if (p == 0 && dim == 3) {
            group = static_cast<int>(in.integer("physical group", 0, max_index));
          } else {
            in.integer("physical tag", int_min, int_max);
          }
        }
        if (dim > 0) {
          const std::int64_t bounding = in.size("bounding entity count", 0, any_integer_max);
          in.check_count_fits(bounding, Input::integer_bytes, "bounding entities");
          for (std::int64_t b = 0; b < bounding; ++b) {
            in.integer("bounding entity tag", int_min, int_max);
          }
        }
        in.end_row(row);
        if (dim == 3) groups.add(tag, group);
      }
    }
    expect_gmsh_marker(in, "$EndEntities");
    if (const auto twin = groups.seal()) {
      in.fail("volume entity " + std::to_string(*twin) + " is defined twice in $Entities");
    }
    return groups;
  }

  template <typename Input>
  GmshTags read_nodes(Input& in, VolumeMeshRows& rows) const {
    const auto [blocks, count] = read_block_header(in, "$Nodes", "nodes", max_index,
                                                   Input::size_bytes + 3 * Input::real_bytes);
    GmshTags tags;
    tags.reserve(static_cast<std::size_t>(count));
    rows.coordinates.reserve(static_cast<std::size_t>(3 * count));
    std::int64_t read = 0;
    for (std::int64_t b = 0; b < blocks; ++b) {
      in.begin_row("node block", b, blocks);
      const std::int64_t dim = in.integer("entity dimension", 0, 3);
      in.integer("entity tag", int_min, int_max);
      const std::int64_t parametric = in.integer("parametric flag", 0, 1);
      const std::int64_t in_block = in.size("block node count", 0, any_integer_max);
      in.end_row("a node block header");
      check_block_count(in, "node block", b, in_block, read, count, "nodes", "$Nodes");
      // Gmsh lists a block's tags, then its coordinates (x y z, then u v w up to the entity's
      // dimension when parametric).
      for (std::int64_t i = 0; i < in_block; ++i) {
        in.begin_row("node tag", i, in_block);
        tags.add(in.size("node tag", 1, any_integer_max), static_cast<int>(read + i));
        in.end_row("a node tag row");
      }
      const std::int64_t parameters = parametric == 1 ? dim : 0;
      for (std::int64_t i = 0; i < in_block; ++i) {
        in.begin_row("node coordinates", i, in_block);
        rows.coordinates.push_back(in.real("x coordinate"));
        rows.coordinates.push_back(in.real("y coordinate"));
        rows.coordinates.push_back(in.real("z coordinate"));
        for (std::int64_t p = 0; p < parameters; ++p) in.real("parametric coordinate");
        in.end_row("a node coordinate row");
      }
      read += in_block;
    }
    expect_gmsh_marker(in, "$EndNodes",
                       " after the " + std::to_string(count) + " nodes the header declares");
    check_total(in, read, count, "nodes", "$Nodes");
    if (const auto twin = tags.seal()) {
      in.fail("node tag " + std::to_string(*twin) + " is defined twice in $Nodes");
    }
    return tags;
  }

  /// The element group of a block of volume elements of `entity`; sets `tagged` when it has
  /// a physical tag.
  template <typename Input>
  int block_group(const Input& in, std::int64_t block, std::int64_t dim, std::int64_t entity,
                  bool& tagged) const {
    const std::string subject = "element block " + std::to_string(block + 1);
    if (dim != 3) {
      in.fail(subject + " holds volume elements but belongs to an entity of dimension " +
              std::to_string(dim));
    }
    if (!volumes) return 0;
    const auto group = volumes->find(entity);
    if (!group) {
      in.fail(subject + " belongs to volume entity " + std::to_string(entity) +
              ", which $Entities does not define");
    }
    if (*group < 0) return 0;
    tagged = true;
    return *group;
  }

  template <typename Input>
  ElementType read_elements(Input& in, const GmshTags& nodes, VolumeMeshRows& rows) {
    elements_read = true;
    // An element takes at least its tag and one node tag.
    const auto [blocks, count] =
        read_block_header(in, "$Elements", "elements", any_integer_max, 2 * Input::size_bytes);
    const GmshElementKind* volume = nullptr;  // kind of the kept elements, once seen
    bool tagged = false;                      // whether a kept element's volume has a group
    std::int64_t read = 0;
    for (std::int64_t b = 0; b < blocks; ++b) {
      in.begin_row("element block", b, blocks);
      const std::int64_t dim = in.integer("entity dimension", 0, 3);
      const std::int64_t entity = in.integer("entity tag", int_min, int_max);
      const std::int64_t type = in.integer("element type", int_min, int_max);
      const GmshElementKind& kind =
          require_gmsh_kind(in, type, "element block " + std::to_string(b + 1));
      const std::int64_t in_block = in.size("block element count", 0, any_integer_max);
      in.end_row("an element block header");
      check_block_count(in, "element block", b, in_block, read, count, "elements", "$Elements");
      const bool keep = kind.role == GmshRole::volume;
      int group = 0;
      if (keep) {
        check_one_volume_type(in, kind, volume);
        group = block_group(in, b, dim, entity, tagged);
        volume = &kind;
      }
      in.check_count_fits(in_block, static_cast<std::size_t>(1 + kind.nodes) * Input::size_bytes,
                          "elements in block " + std::to_string(b + 1));
      const std::string row = "an element row of " + describe(kind);
      for (std::int64_t e = 0; e < in_block; ++e) {
        in.begin_row("element", e, in_block);
        const std::int64_t element = in.size("element tag", 0, any_integer_max);
        for (std::int64_t k = 0; k < kind.nodes; ++k) {
          const std::int64_t tag = in.size("node tag", 0, any_integer_max);
          const auto vertex = nodes.find(tag);
          if (!vertex) fail_undefined_node(in, element, tag);
          if (keep) rows.element_nodes.push_back(*vertex);
        }
        in.end_row(row);
        if (keep) {
          check_distinct_nodes(in, rows.element_nodes, static_cast<int>(kind.nodes), "element",
                               element);
          rows.groups.push_back(group);
        }
      }
      read += in_block;
    }
    expect_gmsh_marker(in, "$EndElements",
                       " after the " + std::to_string(count) + " elements the header declares");
    check_total(in, read, count, "elements", "$Elements");
    if (volume == nullptr) in.fail("$Elements holds no tetrahedra or hexahedra");
    if (!tagged) rows.groups.clear();
    return volume->element_type;
  }
};

template <typename Input>
VolumeMesh read_msh41(Input& in) {
  Msh41 format;
  return read_gmsh_sections(in, format);
}

// ---- Writing ------------------------------------------------------------------------------

/// Values as MSH 4.1 writes them: text tokens, a line per row, or untagged little-endian bytes.
class MshSink {
 public:
  explicit MshSink(bool binary) : m_binary(binary) {}

  void size(std::int64_t value) { put(static_cast<std::uint64_t>(value)); }
  void integer(std::int64_t value) { put(static_cast<std::int32_t>(value)); }
  void real(double value) { put(value); }
  /// Ends a text row: its last separator becomes a line break.
  void end_row() {
    if (!m_binary) m_out.back() = '\n';
  }
  void marker(const char* line) { m_out += line; }
  /// Binary data ends without a line break; the end marker takes its own line.
  void end_section(const char* marker) {
    if (m_binary) m_out += '\n';
    m_out += marker;
  }

  std::string take() { return std::move(m_out); }

 private:
  void put(auto value) {
    if (m_binary) {
      append_binary(m_out, value, Endian::little);
    } else {
      append_number(m_out, value);
      m_out += ' ';
    }
  }

  bool m_binary;
  std::string m_out;
};

/// A $Nodes or $Elements header row for `count` items tagged 1..count.
void write_block_header(MshSink& out, std::size_t blocks, std::int64_t count) {
  out.size(static_cast<std::int64_t>(blocks));
  out.size(count);
  out.size(std::min<std::int64_t>(1, count));
  out.size(count);
  out.end_row();
}

/// The distinct element groups in increasing order; volume entity k + 1 holds groups[k].
std::vector<int> distinct_groups(const VolumeMesh& mesh) {
  std::vector<int> groups(mesh.element_groups.begin(), mesh.element_groups.end());
  std::sort(groups.begin(), groups.end());
  groups.erase(std::unique(groups.begin(), groups.end()), groups.end());
  return groups;
}

}  // namespace

VolumeMesh parse_msh41(MshTextInput& in) { return read_msh41(in); }
VolumeMesh parse_msh41(MshBinaryInput& in) { return read_msh41(in); }

std::string format_msh41(const VolumeMesh& mesh, bool binary) {
  const bool grouped = mesh.element_groups.size() > 0;
  const std::vector<int> groups = grouped ? distinct_groups(mesh) : std::vector<int>{0};
  // Entity tag of element e.
  const auto entity_of = [&](Eigen::Index e) -> std::int64_t {
    if (!grouped) return 1;
    return std::lower_bound(groups.begin(), groups.end(), mesh.element_groups[e]) - groups.begin() +
           1;
  };
  std::vector<Eigen::AlignedBox3d> boxes(groups.size());
  for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
    for (Eigen::Index k = 0; k < mesh.elements.cols(); ++k) {
      boxes[entity_of(e) - 1].extend(mesh.vertices.row(mesh.elements(e, k)).transpose());
    }
  }

  MshSink out(binary);
  out.marker(binary ? "$MeshFormat\n4.1 1 8\n" : "$MeshFormat\n4.1 0 8\n");
  if (binary) out.integer(1);  // the endianness check
  out.end_section("$EndMeshFormat\n$Entities\n");
  for (int dim = 0; dim < 3; ++dim) out.size(0);  // volumes only
  out.size(static_cast<std::int64_t>(groups.size()));
  out.end_row();
  for (std::size_t k = 0; k < groups.size(); ++k) {
    out.integer(static_cast<std::int64_t>(k + 1));
    // Only an empty mesh has an entity without elements; its empty box is written as zeros.
    const bool empty = boxes[k].isEmpty();
    for (int axis = 0; axis < 3; ++axis) out.real(empty ? 0.0 : boxes[k].min()[axis]);
    for (int axis = 0; axis < 3; ++axis) out.real(empty ? 0.0 : boxes[k].max()[axis]);
    out.size(grouped ? 1 : 0);
    if (grouped) out.integer(groups[k]);
    out.size(0);  // no bounding surfaces
    out.end_row();
  }
  out.end_section("$EndEntities\n$Nodes\n");

  write_block_header(out, 1, mesh.num_vertices());
  out.integer(3);
  out.integer(1);
  out.integer(0);  // no parametric coordinates
  out.size(mesh.num_vertices());
  out.end_row();
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    out.size(v + 1);
    out.end_row();
  }
  for (Eigen::Index v = 0; v < mesh.num_vertices(); ++v) {
    for (int axis = 0; axis < 3; ++axis) out.real(mesh.vertices(v, axis));
    out.end_row();
  }
  out.end_section("$EndNodes\n$Elements\n");

  // One block per run of elements of one entity, so the elements keep their order.
  std::vector<std::pair<Eigen::Index, Eigen::Index>> runs;  // [begin, end)
  for (Eigen::Index e = 0; e < mesh.num_elements(); ++e) {
    if (runs.empty() || entity_of(e) != entity_of(runs.back().first)) runs.emplace_back(e, e);
    ++runs.back().second;
  }
  write_block_header(out, runs.size(), mesh.num_elements());
  const std::int64_t type = mesh.element_type == ElementType::tetrahedron ? 4 : 5;
  for (const auto& [begin, end] : runs) {
    out.integer(3);
    out.integer(entity_of(begin));
    out.integer(type);
    out.size(end - begin);
    out.end_row();
    for (Eigen::Index e = begin; e < end; ++e) {
      out.size(e + 1);
      for (Eigen::Index k = 0; k < mesh.elements.cols(); ++k) out.size(mesh.elements(e, k) + 1);
      out.end_row();
    }
  }
  out.end_section("$EndElements\n");
  return out.take();
}

}  // namespace khz::reduced::detail
