#pragma once
// What the MSH 2.2 reader (gmsh.cpp) and the MSH 4.1 reader and writer (gmsh41.cpp) share:
// element types, tag lookup, section markers and the walk over a file's sections.

#include <khz/reduced/io/gmsh.hpp>
#include <khz/reduced/mesh/volume_mesh.hpp>

#include "io/msh_input.hpp"
#include "io/volume_parsing.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace khz::reduced::detail {

/// What the readers do with an element type.
enum class GmshRole {
  boundary,      // points, lines, faces: dropped
  volume,        // kept
  second_order,  // curved volume elements: rejected, suggesting a linear export
  unsupported,   // other volume elements: rejected
};

struct GmshElementKind {
  std::int64_t type;
  std::int64_t nodes;
  const char* name;
  GmshRole role;
  ElementType element_type;  // meaningful for GmshRole::volume only
};

// Binary MSH 4.1 gives no row length, so every type a file may hold needs its node count.
inline constexpr GmshElementKind gmsh_element_kinds[] = {
    {15, 1, "point", GmshRole::boundary, {}},
    {1, 2, "line", GmshRole::boundary, {}},
    {8, 3, "3-node line", GmshRole::boundary, {}},
    {2, 3, "triangle", GmshRole::boundary, {}},
    {9, 6, "6-node triangle", GmshRole::boundary, {}},
    {3, 4, "quadrangle", GmshRole::boundary, {}},
    {16, 8, "8-node quadrangle", GmshRole::boundary, {}},
    {10, 9, "9-node quadrangle", GmshRole::boundary, {}},
    {4, 4, "tetrahedron", GmshRole::volume, ElementType::tetrahedron},
    {5, 8, "hexahedron", GmshRole::volume, ElementType::hexahedron},
    {6, 6, "prism", GmshRole::unsupported, {}},
    {7, 5, "pyramid", GmshRole::unsupported, {}},
    {11, 10, "10-node tetrahedron", GmshRole::second_order, {}},
    {12, 27, "27-node hexahedron", GmshRole::second_order, {}},
    {17, 20, "20-node hexahedron", GmshRole::second_order, {}},
};

inline std::string describe(const GmshElementKind& kind) {
  return "type " + std::to_string(kind.type) + " (" + kind.name + ")";
}

/// The kind of element type `type`; fails through `at` for a type the readers cannot keep or
/// skip. `subject` names the element or block in the file's terms, e.g. "element 7".
template <typename Reporter>
const GmshElementKind& require_gmsh_kind(const Reporter& at, std::int64_t type,
                                         const std::string& subject) {
  const auto* kind = std::find_if(std::begin(gmsh_element_kinds), std::end(gmsh_element_kinds),
                                  [&](const GmshElementKind& k) { return k.type == type; });
  if (kind == std::end(gmsh_element_kinds)) {
    at.fail(subject + " has unsupported type " + std::to_string(type));
  }
  if (kind->role == GmshRole::unsupported || kind->role == GmshRole::second_order) {
    at.fail(
        subject + " has " + describe(*kind) +
        "; only linear tetrahedra (type 4) and hexahedra (type 5) are supported" +
        (kind->role == GmshRole::second_order ? ": export linear elements (gmsh -order 1)" : ""));
  }
  return *kind;
}

/// Fails unless volume elements of `kind` may join those of `*previous` (null before the first).
template <typename Reporter>
void check_one_volume_type(const Reporter& at, const GmshElementKind& kind,
                           const GmshElementKind* previous) {
  if (previous != nullptr && previous != &kind) {
    at.fail("element " + describe(kind) + " mixed with " + describe(*previous) +
            ": a mesh has one element type");
  }
}

template <typename Reporter>
[[noreturn]] void fail_undefined_node(const Reporter& at, std::int64_t element, std::int64_t tag) {
  at.fail("element " + std::to_string(element) + " uses node tag " + std::to_string(tag) +
          ", which $Nodes does not define");
}

/// MSH tags (of nodes, of volume entities), which may be any integers, each with the int it
/// stands for (a vertex index, an element group). A sorted vector rather than a table indexed by
/// tag, so a huge tag costs nothing, and rather than a hash map, so crafted tags cannot force
/// collisions.
class GmshTags {
 public:
  void reserve(std::size_t count) { m_entries.reserve(count); }
  void add(std::int64_t tag, int value) { m_entries.emplace_back(tag, value); }

  /// Sorts the tags; returns a tag added twice, if any. Call before find().
  std::optional<std::int64_t> seal() {
    std::sort(m_entries.begin(), m_entries.end());
    const auto twin =
        std::adjacent_find(m_entries.begin(), m_entries.end(),
                           [](const auto& a, const auto& b) { return a.first == b.first; });
    if (twin == m_entries.end()) return std::nullopt;
    return twin->first;
  }

  /// The value added with `tag`, if any.
  std::optional<int> find(std::int64_t tag) const {
    const auto it = std::lower_bound(
        m_entries.begin(), m_entries.end(), tag,
        [](const std::pair<std::int64_t, int>& entry, std::int64_t t) { return entry.first < t; });
    if (it == m_entries.end() || it->first != tag) return std::nullopt;
    return it->second;
  }

 private:
  std::vector<std::pair<std::int64_t, int>> m_entries;
};

/// True for a well-formed section marker such as "$Nodes", which is then safe to quote.
inline bool is_gmsh_marker(std::string_view token) {
  constexpr std::size_t max_length = 40;
  if (token.size() < 2 || token.size() > max_length || token.front() != '$') return false;
  return std::all_of(token.begin() + 1, token.end(),
                     [](unsigned char c) { return std::isalnum(c) != 0 || c == '_'; });
}

inline std::string describe_gmsh_line(std::string_view first_token) {
  return is_gmsh_marker(first_token) ? std::string(first_token)
                                     : "a line that is not a section marker";
}

/// Moves to the next line, which must be the section marker `marker`; `context` (e.g. " after
/// the 8 nodes the header declares") explains a mismatch.
template <typename Input>
void expect_gmsh_marker(Input& in, std::string_view marker, const std::string& context = {}) {
  std::string_view token;
  if (!in.next_marker(token)) in.fail_at_end("file ends early: expected " + std::string(marker));
  if (token != marker) {
    in.fail("expected " + std::string(marker) + context + ", found " + describe_gmsh_line(token));
  }
}

/// Skips a section the readers do not use, such as $PhysicalNames or $NodeData, by its end
/// marker (as Gmsh does: in a binary file its data could, rarely, hold that line).
template <typename Input>
void skip_gmsh_section(Input& in, std::string_view marker) {
  const std::string end = "$End" + std::string(marker.substr(1));
  std::string_view token;
  do {
    if (!in.next_marker(token)) in.fail_at_end("file ends early: expected " + end);
  } while (token != end);
}

/// Reads the sections after $MeshFormat into a mesh. `format` reads what differs between MSH
/// versions: read_nodes(in, rows) → GmshTags (tag → vertex), read_elements(in, nodes, rows) →
/// ElementType, and read_section(in, marker) → whether it read a section of its own; the other
/// sections are skipped.
template <typename Input, typename Format>
VolumeMesh read_gmsh_sections(Input& in, Format& format) {
  VolumeMeshRows rows;
  std::optional<GmshTags> nodes;
  std::optional<ElementType> type;
  std::string_view token;
  while (in.next_marker(token)) {
    if (token == "$Nodes") {
      if (nodes) in.fail("second $Nodes section; one is supported");
      nodes = format.read_nodes(in, rows);
    } else if (token == "$Elements") {
      if (!nodes) in.fail("$Elements comes before $Nodes");
      if (type) in.fail("second $Elements section; one is supported");
      type = format.read_elements(in, *nodes, rows);
    } else if (format.read_section(in, token)) {
      continue;
    } else if (is_gmsh_marker(token) && !token.starts_with("$End")) {
      skip_gmsh_section(in, token);
    } else {
      in.fail("expected a section such as $Nodes or $Elements, found " + describe_gmsh_line(token));
    }
  }
  if (!nodes) in.fail("file ends without a $Nodes section");
  if (!type) in.fail("file ends without an $Elements section");
  return rows.build(*type);
}

/// The sections of an MSH 4.1 file after $EndMeshFormat (gmsh41.cpp).
VolumeMesh parse_msh41(MshTextInput& in);
VolumeMesh parse_msh41(MshBinaryInput& in);

/// MSH 4.1 ASCII or binary bytes for a validated mesh (gmsh41.cpp).
std::string format_msh41(const VolumeMesh& mesh, bool binary);

}  // namespace khz::reduced::detail
